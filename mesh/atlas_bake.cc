#include "mesh/atlas_bake.h"

#include <algorithm>
#include <cmath>

#include "core/parallel.h"

namespace mesocap {

bool AtlasTexelCoordinate(const TriangleMesh& m, const TangentFrames& frames, const SurfaceMap& map, const Atlas& atlas, int f,
                          int x, int y, Eigen::Vector2f* coordinate) {
  const auto& uv = atlas.corner_uv[f];
  const Eigen::Vector2d q(x + 0.5, y + 0.5), e0 = uv[1] - uv[0], e1 = uv[2] - uv[0], r = q - uv[0];
  const double det = e0.x() * e1.y() - e1.x() * e0.y();
  if (std::abs(det) < 1e-18) return false;
  const double w1 = (r.x() * e1.y() - e1.x() * r.y()) / det, w2 = (e0.x() * r.y() - r.x() * e0.y()) / det, w0 = 1 - w1 - w2;
  if (w0 < -1e-9 || w1 < -1e-9 || w2 < -1e-9) return false;
  const auto& t = m.faces[f];
  const Eigen::Vector3d p = w0 * m.positions[t[0]] + w1 * m.positions[t[1]] + w2 * m.positions[t[2]];
  int nearest = t[0];
  for (int k = 1; k < 3; ++k)
    if ((m.positions[t[k]] - p).squaredNorm() < (m.positions[nearest] - p).squaredNorm()) nearest = t[k];
  const Eigen::Vector3d d = (p - m.positions[nearest]) / map.texel_size;
  const double sx = map.source_x[nearest] + d.dot(frames.s[nearest]), sy = map.source_y[nearest] - d.dot(frames.t[nearest]);
  *coordinate = Eigen::Vector2f(float(std::clamp(sx, 0.0, map.sample_width - 1e-3)), float(std::clamp(sy, 0.0, map.sample_height - 1e-3)));
  return true;
}

SynthMap BakeSurfaceMap(const TriangleMesh& m, const TangentFrames& frames, const SurfaceMap& map, const Atlas& atlas, int gutter,
                        int num_threads) {
  SynthMap out(atlas.size, atlas.size, map.sample_width, map.sample_height, map.method + "-atlas");
  // Faces in bands of atlas rows, so no two tasks write one texel: each band rasterises the rows
  // it owns of every face that reaches them.
  const int bands = std::max(1, std::min(64, atlas.size / 8)), rows = (atlas.size + bands - 1) / bands;
  std::vector<std::vector<int32_t>> band_faces(bands);
  for (int f = 0; f < m.face_count(); ++f) {
    double lo = 1e300, hi = -1e300;
    for (const auto& p : atlas.corner_uv[f]) lo = std::min(lo, p.y()), hi = std::max(hi, p.y());
    for (int b = std::max(0, int(lo) / rows); b <= std::min(bands - 1, int(hi) / rows); ++b) band_faces[b].push_back(f);
  }
  ParallelFor(0, bands, [&](int b) {
    for (int32_t f : band_faces[b]) {
      const auto& uv = atlas.corner_uv[f];
      const int x0 = std::max(0, int(std::floor(std::min({uv[0].x(), uv[1].x(), uv[2].x()})))),
                x1 = std::min(atlas.size - 1, int(std::ceil(std::max({uv[0].x(), uv[1].x(), uv[2].x()})))),
                y0 = std::max(b * rows, int(std::floor(std::min({uv[0].y(), uv[1].y(), uv[2].y()})))),
                y1 = std::min({(b + 1) * rows - 1, atlas.size - 1, int(std::ceil(std::max({uv[0].y(), uv[1].y(), uv[2].y()})))});
      for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) {
          Eigen::Vector2f c;
          if (out.filled(x, y) || !AtlasTexelCoordinate(m, frames, map, atlas, f, x, y, &c)) continue;
          out.Set(x, y, c.x(), c.y(), 0.f, atlas.face_chart[f]);
        }
    }
  }, num_threads);
  // The gutter: each round, empty texels beside filled ones copy one (left, right, up, down).
  for (int round = 0; round < gutter; ++round) {
    SynthMap before = out;
    for (int y = 0; y < atlas.size; ++y)
      for (int x = 0; x < atlas.size; ++x) {
        if (before.filled(x, y)) continue;
        for (const auto& [dx, dy] : {std::pair{-1, 0}, {1, 0}, {0, -1}, {0, 1}}) {
          const int xx = x + dx, yy = y + dy;
          if (xx < 0 || yy < 0 || xx >= atlas.size || yy >= atlas.size || !before.filled(xx, yy)) continue;
          const size_t i = before.index(xx, yy);
          out.Set(x, y, before.source_x[i], before.source_y[i], 0.f, before.patch[i]);
          break;
        }
      }
  }
  return out;
}

}  // namespace mesocap
