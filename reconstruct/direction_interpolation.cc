#include "reconstruct/direction_interpolation.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <sstream>

#include "core/directions.h"

namespace mesocap {
namespace {

double Cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

// Barycentric coordinates of p in triangle abc.
Eigen::Vector3d Barycentric(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c,
                            const Eigen::Vector2d& p) {
  const double area = Cross(b - a, c - a);
  const double wa = Cross(b - p, c - p) / area, wb = Cross(c - p, a - p) / area;
  return {wa, wb, 1.0 - wa - wb};
}

Eigen::Vector2d OnDisk(const Eigen::Vector3d& direction) {
  const Eigen::Vector3d d = direction.normalized();
  return {d.x(), d.y()};
}

double WrapDeg(double deg) {
  deg = std::fmod(deg, 360.0);
  return deg < 0 ? deg + 360.0 : deg;
}

}  // namespace

std::vector<WeightedIndex> MergeWeights(std::vector<WeightedIndex> weights) {
  std::map<int, double> sum;
  for (const WeightedIndex& w : weights) sum[w.index] += w.weight;
  std::vector<WeightedIndex> out;
  for (const auto& [index, weight] : sum)
    if (weight != 0.0) out.push_back({index, weight});
  return out;
}

StatusOr<LightInterpolator> LightInterpolator::Create(const std::vector<Eigen::Vector3d>& directions,
                                                      double min_separation_deg) {
  if (directions.size() < 3)
    return Status::Error("need at least 3 light directions to interpolate, got " + std::to_string(directions.size()));
  for (size_t a = 0; a < directions.size(); ++a)
    for (size_t b = a + 1; b < directions.size(); ++b)
      if (AngleBetweenDeg(directions[a], directions[b]) < min_separation_deg) {
        std::ostringstream msg;
        msg << "light directions " << a << " and " << b << " are duplicates (" << AngleBetweenDeg(directions[a], directions[b])
            << " deg apart)";
        return Status::Error(msg.str());
      }
  LightInterpolator interp;
  for (const auto& d : directions) interp.disk_.push_back(OnDisk(d));
  interp.triangles_ = DelaunayTriangulation(interp.disk_);
  if (interp.triangles_.empty()) return Status::Error("light directions are collinear on the disk: no triangle to blend in");
  std::map<std::pair<int, int>, int> count;
  for (const auto& t : interp.triangles_)
    for (int e = 0; e < 3; ++e) ++count[{std::min(t[e], t[(e + 1) % 3]), std::max(t[e], t[(e + 1) % 3])}];
  for (const auto& [edge, c] : count)
    if (c == 1) interp.hull_edges_.push_back({edge.first, edge.second});
  return interp;
}

bool LightInterpolator::Contains(const Eigen::Vector3d& direction) const {
  const Eigen::Vector2d p = OnDisk(direction);
  for (const auto& t : triangles_)
    if (Barycentric(disk_[t[0]], disk_[t[1]], disk_[t[2]], p).minCoeff() >= -1e-9) return true;
  return false;
}

std::vector<WeightedIndex> LightInterpolator::Weights(const Eigen::Vector3d& direction) const {
  const Eigen::Vector2d p = OnDisk(direction);
  constexpr double kEps = 1e-9;
  for (const auto& t : triangles_) {
    const Eigen::Vector3d w = Barycentric(disk_[t[0]], disk_[t[1]], disk_[t[2]], p);
    if (w.minCoeff() >= -kEps) {
      const Eigen::Vector3d c = w.cwiseMax(0.0) / w.cwiseMax(0.0).sum();
      return MergeWeights({{t[0], c[0]}, {t[1], c[1]}, {t[2], c[2]}});
    }
  }
  // Outside the hull: the hull edge the ray from the disk centre to p crosses last before p.
  int best_edge = -1;
  double best_s = -1, best_u = 0;
  for (size_t e = 0; e < hull_edges_.size(); ++e) {
    const Eigen::Vector2d a = disk_[hull_edges_[e][0]], b = disk_[hull_edges_[e][1]];
    const double denom = Cross(p, b - a);  // solve s p = a + u (b - a)
    if (std::abs(denom) < 1e-15) continue;
    const double s = Cross(a, b - a) / denom, u = Cross(a, p) / denom;
    if (u >= -kEps && u <= 1 + kEps && s > 0 && s <= 1 + kEps && s > best_s) best_edge = int(e), best_s = s, best_u = u;
  }
  if (best_edge < 0) {  // the disk centre is outside the hull too: the closest hull point
    double best_d = 1e300;
    for (size_t e = 0; e < hull_edges_.size(); ++e) {
      const Eigen::Vector2d a = disk_[hull_edges_[e][0]], b = disk_[hull_edges_[e][1]];
      const double u = std::clamp((p - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
      const double d = (a + u * (b - a) - p).squaredNorm();
      if (d < best_d) best_d = d, best_edge = int(e), best_u = u;
    }
  }
  best_u = std::clamp(best_u, 0.0, 1.0);
  return MergeWeights({{hull_edges_[best_edge][0], 1 - best_u}, {hull_edges_[best_edge][1], best_u}});
}

StatusOr<ViewInterpolator> ViewInterpolator::Create(const std::vector<Eigen::Vector3d>& directions, double ring_gap_deg,
                                                    double max_extrapolation, bool even_at_pole) {
  if (directions.empty()) return Status::Error("no view directions");
  std::vector<Eigen::Vector2d> angles;
  for (const auto& d : directions) angles.push_back(AnglesDegFromDirection(d));
  std::vector<int> order(directions.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return angles[a].x() < angles[b].x(); });
  ViewInterpolator interp;
  interp.max_extrapolation_ = std::max(0.0, max_extrapolation);
  interp.even_at_pole_ = even_at_pole;
  for (size_t k = 0; k < order.size(); ++k) {
    if (k == 0 || angles[order[k]].x() - angles[order[k - 1]].x() > ring_gap_deg) interp.rings_.emplace_back();
    interp.rings_.back().views.push_back(order[k]);
  }
  for (Ring& ring : interp.rings_) {
    std::sort(ring.views.begin(), ring.views.end(), [&](int a, int b) { return angles[a].y() < angles[b].y(); });
    for (int v : ring.views) {
      ring.phi_deg.push_back(angles[v].y());
      ring.theta_deg.push_back(angles[v].x());
    }
    ring.mean_theta_deg = std::accumulate(ring.theta_deg.begin(), ring.theta_deg.end(), 0.0) / ring.views.size();
    for (size_t k = 1; k < ring.phi_deg.size(); ++k)
      if (ring.phi_deg[k] - ring.phi_deg[k - 1] < 1e-6 && ring.theta_deg[k] > 1e-3)
        return Status::Error("two view directions share incidence ring and azimuth (" + std::to_string(ring.phi_deg[k]) + " deg)");
  }
  return interp;
}

std::vector<WeightedIndex> ViewInterpolator::AlongRing(const Ring& ring, double phi_deg, double* theta_deg) const {
  const int m = static_cast<int>(ring.views.size());
  if (m == 1) {
    *theta_deg = ring.theta_deg[0];
    return {{ring.views[0], 1.0}};
  }
  // The polyline segment k -> k+1 (cyclic) whose azimuth span holds phi.
  phi_deg = WrapDeg(phi_deg);
  int k = m - 1;  // wraps from the last view to the first
  for (int j = 0; j + 1 < m; ++j)
    if (phi_deg >= ring.phi_deg[j] && phi_deg < ring.phi_deg[j + 1]) k = j;
  const int next = (k + 1) % m;
  const double span = WrapDeg(ring.phi_deg[next] - ring.phi_deg[k]);
  const double t = span > 0 ? WrapDeg(phi_deg - ring.phi_deg[k]) / span : 0.0;
  *theta_deg = (1 - t) * ring.theta_deg[k] + t * ring.theta_deg[next];
  return {{ring.views[k], 1 - t}, {ring.views[next], t}};
}

std::vector<WeightedIndex> ViewInterpolator::Weights(const Eigen::Vector3d& direction) const {
  const Eigen::Vector2d angles = AnglesDegFromDirection(direction);
  const double theta = angles.x(), phi = angles.y();
  const int rings = ring_count();
  std::vector<double> ring_theta(rings);
  std::vector<std::vector<WeightedIndex>> along(rings);
  for (int r = 0; r < rings; ++r) along[r] = AlongRing(rings_[r], phi, &ring_theta[r]);
  if (rings == 1) return MergeWeights(along[0]);
  // The pair of neighbouring rings that brackets theta; the end pairs extrapolate.
  int r = 0;
  while (r + 2 < rings && theta > ring_theta[r + 1]) ++r;
  // The coordinate incidence is interpolated in: theta, or 1 - cos(theta) from a top view.
  constexpr double kTopViewDeg = 5.0;
  const bool from_pole = even_at_pole_ && r == 0 && ring_theta[0] < kTopViewDeg;
  const auto coordinate = [&](double deg) { return from_pole ? 1.0 - std::cos(DegToRad(deg)) : deg; };
  const double span = coordinate(ring_theta[r + 1]) - coordinate(ring_theta[r]);
  const double s = std::clamp(std::abs(span) > 1e-12 ? (coordinate(theta) - coordinate(ring_theta[r])) / span : 0.0,
                              -max_extrapolation_, 1.0 + max_extrapolation_);
  std::vector<WeightedIndex> out;
  for (const auto& w : along[r]) out.push_back({w.index, (1 - s) * w.weight});
  for (const auto& w : along[r + 1]) out.push_back({w.index, s * w.weight});
  return MergeWeights(out);
}

}  // namespace mesocap
