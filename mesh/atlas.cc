#include "mesh/atlas.h"

#include "mesh/lscm.h"
#include "mesh/triangle_raster.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>


#include <Eigen/Eigenvalues>

namespace mesocap {
namespace {

constexpr int kMaxSplits = 24;  // halvings of one chart before its faces go one by one

using Chart = std::vector<int32_t>;  // faces

// Connected groups of `faces` (through edges) whose `label` is the same.
std::vector<Chart> Components(const Chart& faces, const std::vector<int>& label, const std::vector<std::array<int32_t, 3>>& nb,
                              std::vector<int>& mark, int stamp) {
  for (int32_t f : faces) mark[f] = stamp;
  std::vector<Chart> out;
  for (int32_t f : faces) {
    if (mark[f] != stamp) continue;
    Chart c{f};
    mark[f] = stamp + 1;
    for (size_t i = 0; i < c.size(); ++i)
      for (int32_t g : nb[c[i]])
        if (g >= 0 && mark[g] == stamp && label[g] == label[c[i]]) mark[g] = stamp + 1, c.push_back(g);
    out.push_back(std::move(c));
  }
  return out;
}

// Halves a chart across the longest extent of its faces' centres.
std::pair<Chart, Chart> Split(const TriangleMesh& m, const Chart& chart) {
  std::vector<Eigen::Vector3d> centre(chart.size());
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
  for (size_t i = 0; i < chart.size(); ++i) {
    const auto& t = m.faces[chart[i]];
    centre[i] = (m.positions[t[0]] + m.positions[t[1]] + m.positions[t[2]]) / 3;
    lo = lo.cwiseMin(centre[i]), hi = hi.cwiseMax(centre[i]);
  }
  int axis = 0;
  (hi - lo).maxCoeff(&axis);
  std::vector<size_t> order(chart.size());
  std::iota(order.begin(), order.end(), 0);
  std::nth_element(order.begin(), order.begin() + order.size() / 2, order.end(),
                   [&](size_t a, size_t b) { return centre[a][axis] < centre[b][axis]; });
  Chart a, b;
  for (size_t i = 0; i < order.size(); ++i) (i < order.size() / 2 ? a : b).push_back(chart[order[i]]);
  return {a, b};
}

struct Flat {
  Chart faces;
  std::vector<std::array<Eigen::Vector2d, 3>> uv;  // surface units, turned so the longer side runs along u
  Eigen::Vector2d extent;
};

// Scales LSCM's output to surface units (its area the chart's) and turns it to its principal axes.
void Normalise(const TriangleMesh& m, Flat& c) {
  double area3 = 0, area2 = 0;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (size_t i = 0; i < c.faces.size(); ++i) {
    area3 += m.FaceArea(c.faces[i]);
    const Eigen::Vector2d a = c.uv[i][1] - c.uv[i][0], b = c.uv[i][2] - c.uv[i][0];
    area2 += 0.5 * std::abs(a.x() * b.y() - a.y() * b.x());
    for (const auto& p : c.uv[i]) mean += p;
  }
  mean /= 3.0 * c.faces.size();
  const double scale = area2 > 0 ? std::sqrt(area3 / area2) : 1;
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
  for (const auto& t : c.uv)
    for (const auto& p : t) cov += (p - mean) * (p - mean).transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(cov);
  Eigen::Matrix2d R = eig.eigenvectors().transpose().colwise().reverse();  // major axis first
  if (R.determinant() < 0) R.row(1) *= -1;
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(1e300), hi = -lo;
  for (auto& t : c.uv)
    for (auto& p : t) p = scale * (R * (p - mean)), lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  for (auto& t : c.uv)
    for (auto& p : t) p -= lo;
  c.extent = hi - lo;
}

// Shelf packing of the charts' boxes at `k` texels per unit; false when they do not fit.
bool Pack(const std::vector<Flat>& charts, const std::vector<size_t>& order, double k, int size, int gutter,
          std::vector<Eigen::Vector2d>* origin) {
  double x = 0, y = 0, shelf = 0;
  origin->assign(charts.size(), Eigen::Vector2d::Zero());
  for (size_t i : order) {
    const double w = std::ceil(k * charts[i].extent.x()) + 2 * gutter, h = std::ceil(k * charts[i].extent.y()) + 2 * gutter;
    if (w > size) return false;
    if (x + w > size) x = 0, y += shelf, shelf = 0;
    if (y + h > size) return false;
    (*origin)[i] = Eigen::Vector2d(x + gutter, y + gutter);
    x += w, shelf = std::max(shelf, h);
  }
  return true;
}

}  // namespace

StatusOr<Atlas> BuildAtlas(const TriangleMesh& m, const AtlasOptions& o) {
  if (o.size < 16 || o.size > 16384) return Status::Error("the atlas size must be 16..16384 texels");
  const auto nb = FaceNeighbours(m);
  std::vector<int> label(m.face_count());
  for (int f = 0; f < m.face_count(); ++f) {
    const Eigen::Vector3d n = m.FaceNormal(f);
    int axis = 0;
    n.cwiseAbs().maxCoeff(&axis);
    label[f] = 2 * axis + (n[axis] < 0);
  }
  std::vector<int> mark(m.face_count(), 0);
  int stamp = 1;
  Chart all(m.face_count());
  std::iota(all.begin(), all.end(), 0);
  std::vector<std::pair<Chart, int>> pending;  // a chart and how often it was split
  for (Chart& c : Components(all, label, nb, mark, stamp)) pending.push_back({std::move(c), 0});
  stamp += 2;
  std::vector<Flat> flats;
  const std::vector<int> one_label(m.face_count(), 0);
  while (!pending.empty()) {
    auto [chart, splits] = std::move(pending.back());
    pending.pop_back();
    auto uv = FlattenByLscm(m, chart);
    if (!uv.empty()) {
      flats.push_back({std::move(chart), std::move(uv), {}});
      continue;
    }
    if (splits >= kMaxSplits) {  // give up on this chart's shape: its faces one by one
      for (int32_t f : chart) pending.push_back({Chart{f}, splits});
      continue;
    }
    auto [a, b] = Split(m, chart);
    for (Chart* half : {&a, &b}) {
      for (Chart& c : Components(*half, one_label, nb, mark, stamp)) pending.push_back({std::move(c), splits + 1});
      stamp += 2;
    }
  }
  for (Flat& c : flats) Normalise(m, c);

  // The largest density at which the boxes fit, by bisection.
  std::vector<size_t> order(flats.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return flats[a].extent.y() > flats[b].extent.y(); });
  double area = 0;
  for (int f = 0; f < m.face_count(); ++f) area += m.FaceArea(f);
  double lo = 0, hi = o.size / std::sqrt(std::max(area, 1e-300));
  std::vector<Eigen::Vector2d> origin;
  for (int it = 0; it < 40; ++it) {
    const double k = 0.5 * (lo + hi);
    (Pack(flats, order, k, o.size, o.gutter, &origin) ? lo : hi) = k;
  }
  if (!(lo > 0) || !Pack(flats, order, lo, o.size, o.gutter, &origin))
    return Status::Error("the mesh's " + std::to_string(flats.size()) + " charts do not fit a " + std::to_string(o.size) + " texel atlas");
  Atlas atlas;
  atlas.size = o.size, atlas.charts = int(flats.size()), atlas.texels_per_unit = lo;
  atlas.corner_uv.resize(m.face_count());
  atlas.face_chart.assign(m.face_count(), -1);
  double covered = 0;
  for (size_t c = 0; c < flats.size(); ++c)
    for (size_t i = 0; i < flats[c].faces.size(); ++i) {
      const int32_t f = flats[c].faces[i];
      for (int k = 0; k < 3; ++k) atlas.corner_uv[f][k] = origin[c] + lo * flats[c].uv[i][k];
      atlas.face_chart[f] = int32_t(c);
      const Eigen::Vector2d a = atlas.corner_uv[f][1] - atlas.corner_uv[f][0], b = atlas.corner_uv[f][2] - atlas.corner_uv[f][0];
      covered += 0.5 * std::abs(a.x() * b.y() - a.y() * b.x());
    }
  atlas.fill = covered / (double(o.size) * o.size);
  return atlas;
}

StatusOr<Atlas> AtlasFromMeshUvs(const TriangleMesh& m, const AtlasOptions& o) {
  if (o.size < 16 || o.size > 16384) return Status::Error("the atlas size must be 16..16384 texels");
  if (m.corner_uv.size() != m.faces.size() || m.faces.empty()) return Status::Error("the mesh has no UVs");
  Atlas atlas;
  atlas.size = o.size;
  atlas.corner_uv.resize(m.face_count());
  double uv_area = 0, area = 0;
  for (int f = 0; f < m.face_count(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector2d& t = m.corner_uv[f][k];
      if (!(t.x() >= 0 && t.x() <= 1 && t.y() >= 0 && t.y() <= 1))
        return Status::Error("face " + std::to_string(f) + "'s UVs lie outside [0, 1] (a tiled texture, not an atlas)");
      atlas.corner_uv[f][k] = Eigen::Vector2d(t.x() * o.size, (1 - t.y()) * o.size);
    }
    const Eigen::Vector2d a = atlas.corner_uv[f][1] - atlas.corner_uv[f][0], b = atlas.corner_uv[f][2] - atlas.corner_uv[f][0];
    const double texels = 0.5 * std::abs(a.x() * b.y() - a.y() * b.x());
    if (!(texels > 1e-6)) return Status::Error("face " + std::to_string(f) + " has no area in the UVs");
    uv_area += texels, area += m.FaceArea(f);
  }
  // Charts: faces joined by an edge whose two corners have the same UVs on both sides.
  const auto nb = FaceNeighbours(m);
  atlas.face_chart.assign(m.face_count(), -1);
  auto uv_of = [&](int f, int32_t v) {
    for (int k = 0; k < 3; ++k)
      if (m.faces[f][k] == v) return m.corner_uv[f][k];
    return Eigen::Vector2d(-1, -1);
  };
  for (int f = 0; f < m.face_count(); ++f) {
    if (atlas.face_chart[f] >= 0) continue;
    std::vector<int32_t> stack{f};
    atlas.face_chart[f] = atlas.charts;
    while (!stack.empty()) {
      const int g = stack.back();
      stack.pop_back();
      for (int k = 0; k < 3; ++k) {
        const int h = nb[g][k];
        if (h < 0 || atlas.face_chart[h] >= 0) continue;
        const int32_t a = m.faces[g][k], b = m.faces[g][(k + 1) % 3];
        if ((uv_of(g, a) - uv_of(h, a)).norm() > 1e-6 || (uv_of(g, b) - uv_of(h, b)).norm() > 1e-6) continue;
        atlas.face_chart[h] = atlas.charts;
        stack.push_back(h);
      }
    }
    ++atlas.charts;
  }
  // Overlap: texel centres strictly inside faces of two charts, or of one chart folded onto itself.
  std::vector<int32_t> owner(size_t(o.size) * o.size, -1);
  long covered = 0, overlapping = 0;
  const double strictly_inside = std::nextafter(1e-6, 1.0);
  for (int f = 0; f < m.face_count(); ++f)
    ForEachGridPointIn(atlas.corner_uv[f], o.size, 0, o.size, 0.5, strictly_inside, [&](int x, int y, const Eigen::Vector3d&) {
      int32_t& who = owner[size_t(y) * o.size + x];
      if (who < 0) who = f, ++covered;
      else ++overlapping;
    });
  if (overlapping > std::max(0L, covered / 1000))
    return Status::Error("its UV charts overlap (" + std::to_string(overlapping) + " texels of " + std::to_string(o.size) + "^2 covered twice)");
  atlas.fill = uv_area / (double(o.size) * o.size);
  atlas.texels_per_unit = area > 0 ? std::sqrt(uv_area / area) : 0;
  return atlas;
}

}  // namespace mesocap
