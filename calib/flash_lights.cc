#include "calib/flash_lights.h"

#include <ceres/ceres.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace mesocap {
namespace {

// Perpendicular offset of the light from a ray, divided by its distance along the ray: the sine
// of the angle between the ray and the direction to the light (angular error, unitless).
struct RayAngleCost {
  RayAngleCost(const Eigen::Vector3d& o, const Eigen::Vector3d& d) : o_(o), d_(d) {}
  template <typename T>
  bool operator()(const T* L, T* r) const {
    const T v[3] = {L[0] - T(o_.x()), L[1] - T(o_.y()), L[2] - T(o_.z())};
    const T along = v[0] * T(d_.x()) + v[1] * T(d_.y()) + v[2] * T(d_.z());
    const T norm = ceres::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    r[0] = (v[0] - along * T(d_.x())) / norm;
    r[1] = (v[1] - along * T(d_.y())) / norm;
    r[2] = (v[2] - along * T(d_.z())) / norm;
    return true;
  }
  Eigen::Vector3d o_, d_;
};

Highlight FindHighlight(const CameraModel& camera, const SphereEstimate& sphere, int index, const Image& shot,
                        const HighlightOptions& o) {
  Highlight h;
  h.sphere = index;
  const Eigen::Vector2d c = sphere.image_centre_px;
  const double reach = 0.97 * sphere.image_radius_px;
  const int W = shot.width(), H = shot.height();
  // Whiteness = min(R, G, B): the coloured base is bright in one or two channels, the
  // highlight in all three (and saturates there, which the centroid below tolerates).
  auto whiteness = [&](int x, int y) {
    const float* p = shot.pixel(x, y);
    return shot.channels() >= 3 ? std::min({p[0], p[1], p[2]}) : p[0];
  };
  double peak = -1;
  int px = 0, py = 0;
  for (int y = std::max(0, int(c.y() - reach)); y <= std::min(H - 1, int(c.y() + reach)); ++y)
    for (int x = std::max(0, int(c.x() - reach)); x <= std::min(W - 1, int(c.x() + reach)); ++x) {
      if ((Eigen::Vector2d(x, y) - c).norm() > reach) continue;
      const double w = whiteness(x, y);
      if (w > peak) {
        peak = w;
        px = x;
        py = y;
      }
    }
  if (peak < o.min_whiteness) {
    h.why_not = "no highlight (ball in shadow or flash behind it)";
    return h;
  }
  const int R = int(std::ceil(o.max_blob_radius_px)) + 2;
  double sw = 0, sx = 0, sy = 0, far = 0;
  for (int y = std::max(0, py - R); y <= std::min(H - 1, py + R); ++y)
    for (int x = std::max(0, px - R); x <= std::min(W - 1, px + R); ++x) {
      const double w = whiteness(x, y) - o.blob_fraction * peak;
      if (w <= 0) continue;
      sw += w;
      sx += w * x;
      sy += w * y;
      far = std::max(far, std::hypot(x - px, y - py));
    }
  if (far > o.max_blob_radius_px) {
    h.why_not = "bright area too large for a mirror highlight (saturated base or glare)";
    return h;
  }
  h.pixel = {sx / sw, sy / sw};
  // The ray through the highlight meets the ball; reflect the view direction about the normal.
  const Eigen::Vector3d d = camera.PixelToRay(h.pixel);
  const double b = d.dot(sphere.center_m);
  const double disc = b * b - (sphere.center_m.squaredNorm() - sphere.radius_m * sphere.radius_m);
  if (disc < 0) {
    h.why_not = "highlight outside the ball's outline";
    return h;
  }
  h.origin_m = (b - std::sqrt(disc)) * d;
  const Eigen::Vector3d n = (h.origin_m - sphere.center_m).normalized();
  h.direction = (d - 2 * d.dot(n) * n).normalized();
  h.found = true;
  return h;
}

}  // namespace

Json LightEstimate::ToJson() const {
  Json hs = Json::array();
  for (const auto& h : highlights) {
    Json jh = {{"sphere", h.sphere}, {"found", h.found}};
    if (h.found) jh["pixel"] = mesocap::ToJson(h.pixel);
    else jh["why_not"] = h.why_not;
    hs.push_back(jh);
  }
  Json j = {{"ok", ok}, {"highlights_used", highlights_used}, {"highlights", hs}};
  if (!flag.empty()) j["flag"] = flag;
  if (ok) {
    j["light_m"] = mesocap::ToJson(light_m);
    j["position_stddev_mm"] = 1000 * std::sqrt(covariance_m2.trace());
    j["rms_ray_miss_mm"] = rms_ray_miss_mm;
  }
  return j;
}

LightEstimate EstimateFlash(const CameraModel& camera, const std::vector<SphereEstimate>& spheres, const Image& shot,
                            const HighlightOptions& options) {
  LightEstimate est;
  std::vector<const Highlight*> used;
  for (size_t i = 0; i < spheres.size(); ++i) est.highlights.push_back(FindHighlight(camera, spheres[i], int(i), shot, options));
  for (const auto& h : est.highlights)
    if (h.found) used.push_back(&h);
  est.highlights_used = int(used.size());
  if (int(used.size()) < options.min_highlights) {
    est.flag = "only " + std::to_string(used.size()) + " usable highlight(s); need " +
               std::to_string(options.min_highlights);
    return est;
  }
  // Closed form: the point nearest to all rays, then the angular refinement.
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
  for (const Highlight* h : used) {
    const Eigen::Matrix3d P = Eigen::Matrix3d::Identity() - h->direction * h->direction.transpose();
    A += P;
    rhs += P * h->origin_m;
  }
  const Eigen::Vector3d initial = A.ldlt().solve(rhs);
  double L[3] = {initial.x(), initial.y(), initial.z()};
  ceres::Problem problem;
  for (const Highlight* h : used)
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<RayAngleCost, 3, 3>(new RayAngleCost(h->origin_m, h->direction)),
                             nullptr, L);
  ceres::Solver::Options solver;
  solver.linear_solver_type = ceres::DENSE_QR;
  ceres::Solver::Summary summary;
  ceres::Solve(solver, &problem, &summary);
  est.light_m = {L[0], L[1], L[2]};
  double sq = 0;
  for (const Highlight* h : used) {
    const Eigen::Vector3d v = est.light_m - h->origin_m;
    const double miss = (v - v.dot(h->direction) * h->direction).norm();
    sq += miss * miss;
  }
  est.rms_ray_miss_mm = 1000 * std::sqrt(sq / used.size());
  // Covariance for a nominal 0.1 px highlight error, about 1e-3 rad of ray angle.
  ceres::Covariance::Options cov_options;
  ceres::Covariance covariance(cov_options);
  std::vector<std::pair<const double*, const double*>> blocks = {{L, L}};
  if (covariance.Compute(blocks, &problem)) {
    double c[9];
    covariance.GetCovarianceBlock(L, L, c);
    const double sigma2 = 1e-6;
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k) est.covariance_m2(r, k) = sigma2 * c[r * 3 + k];
  }
  est.ok = summary.IsSolutionUsable() && est.light_m.allFinite();
  if (!est.ok) est.flag = "light solve failed: " + summary.message;
  return est;
}

}  // namespace mesocap
