#include "mesh/atlas_texels.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "core/parallel.h"
#include "mesh/triangle_raster.h"

namespace mesocap {

Eigen::Vector3d AtlasWeights(const Atlas& atlas, int f, const Eigen::Vector2d& q) { return Barycentric(atlas.corner_uv[f], q); }

namespace {

constexpr double kInside = -1e-9;  // a centre on a shared edge belongs to both faces; the first takes it

// Per atlas texel, the first face (in face order) whose triangle holds its centre, and the weights.
void Rasterise(const Atlas& atlas, std::vector<int32_t>* face_of, std::vector<Eigen::Vector3f>* weights_of, int num_threads) {
  const int n = atlas.size;
  face_of->assign(size_t(n) * n, -1);
  weights_of->assign(size_t(n) * n, Eigen::Vector3f::Zero());
  // Faces in bands of rows, so no two tasks write one texel.
  const int bands = std::max(1, std::min(64, n / 8)), rows = (n + bands - 1) / bands;
  std::vector<std::vector<int32_t>> band_faces(bands);
  for (int f = 0; f < int(atlas.corner_uv.size()); ++f) {
    double lo = 1e300, hi = -1e300;
    for (const auto& p : atlas.corner_uv[f]) lo = std::min(lo, p.y()), hi = std::max(hi, p.y());
    for (int b = std::max(0, int(lo) / rows); b <= std::min(bands - 1, int(hi) / rows); ++b) band_faces[b].push_back(f);
  }
  ParallelFor(0, bands, [&](int b) {
    for (int32_t f : band_faces[b])
      ForEachGridPointIn(atlas.corner_uv[f], n, b * rows, std::min(n, (b + 1) * rows), 0.5, kInside,
                         [&](int x, int y, const Eigen::Vector3d& w) {
                           const size_t i = size_t(y) * n + x;
                           if ((*face_of)[i] >= 0) return;
                           (*face_of)[i] = f;
                           (*weights_of)[i] = w.cast<float>();
                         });
  }, num_threads);
  // Texels no face holds the centre of but a face's edge crosses (the whole of a sliver, thinner
  // than a texel, lies in such texels) take the first such face, extended to the texel's centre
  // (weights a little outside [0, 1]), so a texel's value is the one at its centre: every point
  // of every face lies in a dense texel or beside one, so renders have no holes.
  for (int f = 0; f < int(atlas.corner_uv.size()); ++f)
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector2d a = atlas.corner_uv[f][k], b = atlas.corner_uv[f][(k + 1) % 3];
      const int steps = 1 + int(std::ceil(2 * (b - a).norm()));
      for (int i = 0; i <= steps; ++i) {
        const double s = double(i) / steps;
        const Eigen::Vector2d q = (1 - s) * a + s * b;
        const int x = int(std::floor(q.x())), y = int(std::floor(q.y()));
        if (x < 0 || y < 0 || x >= n || y >= n || (*face_of)[size_t(y) * n + x] >= 0) continue;
        // A sliver's plane carries the centre far off the surface: its crossing point instead.
        Eigen::Vector3d w = AtlasWeights(atlas, f, Eigen::Vector2d(x + 0.5, y + 0.5));
        if (w.minCoeff() < -0.5 || w.maxCoeff() > 1.5) w = Eigen::Vector3d::Zero(), w[k] = 1 - s, w[(k + 1) % 3] = s;
        (*face_of)[size_t(y) * n + x] = f;
        (*weights_of)[size_t(y) * n + x] = w.cast<float>();
      }
    }
}

struct CellKey {
  int64_t x, y, z;
  bool operator==(const CellKey& o) const { return x == o.x && y == o.y && z == o.z; }
};
struct CellHash {
  size_t operator()(const CellKey& k) const { return size_t(k.x * 73856093 ^ k.y * 19349663 ^ k.z * 83492791); }
};

// Neighbours: the 8 texels around in the chart, and for texels on a chart's border the border
// texels of other charts within 1.5 local spacings whose faces face the same way.
VertexAdjacency Neighbours(const TriangleMesh& mesh, const Atlas& atlas, const AtlasTexels& t) {
  const int n = t.count();
  std::vector<std::vector<int32_t>> lists(n);
  std::vector<uint8_t> border(n, 0);
  std::vector<double> reach(n, 1.5 * t.spacing);
  for (int d = 0; d < n; ++d) {
    double sum = 0;
    int four = 0;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        if (!dx && !dy) continue;
        const int e = t.At(t.x[d] + dx, t.y[d] + dy);
        if (e < 0) {
          border[d] = 1;
          continue;
        }
        lists[d].push_back(e);
        if (!dx || !dy) sum += (t.position[e] - t.position[d]).norm(), ++four;
      }
    if (four) reach[d] = 1.5 * std::max(t.spacing, sum / four);
  }
  const double cell = 1.5 * t.spacing;
  auto key = [&](const Eigen::Vector3d& p) {
    return CellKey{int64_t(std::floor(p.x() / cell)), int64_t(std::floor(p.y() / cell)), int64_t(std::floor(p.z() / cell))};
  };
  std::unordered_map<CellKey, std::vector<int32_t>, CellHash> grid;
  for (int d = 0; d < n; ++d)
    if (border[d]) grid[key(t.position[d])].push_back(d);
  for (int d = 0; d < n; ++d) {
    if (!border[d]) continue;
    const CellKey k = key(t.position[d]);
    const int span = int(std::ceil(reach[d] / cell));
    const int chart = atlas.face_chart[t.face[d]];
    const Eigen::Vector3d normal = mesh.FaceNormal(t.face[d]);
    for (int64_t z = k.z - span; z <= k.z + span; ++z)
      for (int64_t y = k.y - span; y <= k.y + span; ++y)
        for (int64_t x = k.x - span; x <= k.x + span; ++x) {
          const auto it = grid.find({x, y, z});
          if (it == grid.end()) continue;
          for (int32_t e : it->second)
            if (atlas.face_chart[t.face[e]] != chart && (t.position[e] - t.position[d]).norm() <= reach[d] &&
                mesh.FaceNormal(t.face[e]).dot(normal) > 0)
              lists[d].push_back(e);
        }
  }
  // Symmetric: a cross-chart pair found from either side joins both lists.
  for (int d = 0; d < n; ++d)
    for (int32_t e : lists[d])
      if (atlas.face_chart[t.face[e]] != atlas.face_chart[t.face[d]] &&
          std::find(lists[e].begin(), lists[e].end(), d) == lists[e].end())
        lists[e].push_back(d);
  VertexAdjacency adj;
  adj.offsets.assign(1, 0);
  for (auto& l : lists) {
    std::sort(l.begin(), l.end());
    l.erase(std::unique(l.begin(), l.end()), l.end());
    adj.list.insert(adj.list.end(), l.begin(), l.end());
    adj.offsets.push_back(int32_t(adj.list.size()));
  }
  return adj;
}

}  // namespace

AtlasTexels BuildAtlasTexels(const TriangleMesh& mesh, const Atlas& atlas, int num_threads) {
  AtlasTexels t;
  t.size = atlas.size;
  t.spacing = atlas.texels_per_unit > 0 ? 1 / atlas.texels_per_unit : 0;
  std::vector<int32_t> face_of;
  std::vector<Eigen::Vector3f> weights_of;
  Rasterise(atlas, &face_of, &weights_of, num_threads);
  t.index.assign(face_of.size(), -1);
  for (int y = 0; y < atlas.size; ++y)
    for (int x = 0; x < atlas.size; ++x) {
      const size_t i = size_t(y) * atlas.size + x;
      const int f = face_of[i];
      if (f < 0) continue;
      t.index[i] = t.count();
      t.x.push_back(x), t.y.push_back(y), t.face.push_back(f), t.weights.push_back(weights_of[i]);
      const auto& c = mesh.faces[f];
      const Eigen::Vector3f& w = weights_of[i];
      t.position.push_back(double(w[0]) * mesh.positions[c[0]] + double(w[1]) * mesh.positions[c[1]] + double(w[2]) * mesh.positions[c[2]]);
    }
  t.neighbours = Neighbours(mesh, atlas, t);
  return t;
}

}  // namespace mesocap
