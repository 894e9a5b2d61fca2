#include "mesh/atlas_bake.h"

#include <algorithm>
#include <cmath>

namespace mesocap {

Eigen::Vector2f ContinuedCoordinate(const TriangleMesh& m, const TangentFrames& frames, const SurfaceMap& map, int f,
                                    const Eigen::Vector3d& p) {
  const auto& t = m.faces[f];
  int nearest = t[0];
  for (int k = 1; k < 3; ++k)
    if ((m.positions[t[k]] - p).squaredNorm() < (m.positions[nearest] - p).squaredNorm()) nearest = t[k];
  const Eigen::Vector3d d = (p - m.positions[nearest]) / map.texel_size;
  const double sx = map.source_x[nearest] + d.dot(frames.s[nearest]), sy = map.source_y[nearest] - d.dot(frames.t[nearest]);
  return {float(std::clamp(sx, 0.0, map.sample_width - 1e-3)), float(std::clamp(sy, 0.0, map.sample_height - 1e-3))};
}

SynthMap BakeSurfaceMap(const TriangleMesh& m, const TangentFrames& frames, const SurfaceMap& map, const Atlas& atlas,
                        const AtlasTexels& texels, int gutter) {
  SynthMap out(atlas.size, atlas.size, map.sample_width, map.sample_height, map.method + "-atlas");
  for (int d = 0; d < texels.count(); ++d) {
    const Eigen::Vector2f c = ContinuedCoordinate(m, frames, map, texels.face[d], texels.position[d]);
    out.Set(texels.x[d], texels.y[d], c.x(), c.y(), 0.f, atlas.face_chart[texels.face[d]]);
  }
  FillAtlasGutter(&out, gutter);
  return out;
}

void FillAtlasGutter(SynthMap* out, int gutter) {
  for (int round = 0; round < gutter; ++round) {
    const SynthMap before = *out;
    for (int y = 0; y < out->height; ++y)
      for (int x = 0; x < out->width; ++x) {
        if (before.filled(x, y)) continue;
        for (const auto& [dx, dy] : {std::pair{-1, 0}, {1, 0}, {0, -1}, {0, 1}}) {
          const int xx = x + dx, yy = y + dy;
          if (xx < 0 || yy < 0 || xx >= out->width || yy >= out->height || !before.filled(xx, yy)) continue;
          const size_t i = before.index(xx, yy);
          out->Set(x, y, before.source_x[i], before.source_y[i], before.rotation_deg[i], before.patch[i]);
          break;
        }
      }
  }
}

}  // namespace mesocap
