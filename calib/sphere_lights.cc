#include "calib/sphere_lights.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include "core/median.h"

namespace mesocap {
namespace {

float Brightness(const Image& im, int x, int y) {
  const float* p = im.pixel(x, y);
  return *std::max_element(p, p + std::min(im.channels(), 3));
}

std::string Fixed(double v, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

}  // namespace

std::string SphereLightsOptions::Check() const {
  if (!(saturation > 0 && saturation <= 1)) return "saturation level must be in (0, 1]";
  if (!(blob_level > 0 && blob_level < 1)) return "highlight blob level must be in (0, 1)";
  if (!(min_peak_over_median > 1)) return "a highlight must be brighter than the sphere's median (ratio > 1)";
  if (!(max_blob_radius > 0 && max_blob_radius < 1)) return "max highlight radius must be in (0, 1) of the sphere's";
  if (!(max_rim_radius > 0 && max_rim_radius <= 1)) return "max rim radius must be in (0, 1] of the sphere's";
  return "";
}

Json SphereCircle::ToJson() const { return {{"centre_px", mesocap::ToJson(centre_px)}, {"radius_px", radius_px}}; }

Json SphereLight::ToJson() const {
  Json j = {{"found", found}};
  if (!found) {
    j["why_not"] = why_not;
    return j;
  }
  j["highlight_px"] = mesocap::ToJson(highlight_px);
  j["blob_pixels"] = blob_pixels;
  j["saturated"] = saturated;
  j["normal"] = mesocap::ToJson(normal);
  j["light_dir"] = mesocap::ToJson(light_dir);
  return j;
}

StatusOr<SphereCircle> CircleFromMask(const Image& mask) {
  if (mask.empty()) return Status::Error("the sphere mask is empty");
  double area = 0, sx = 0, sy = 0;
  bool touches_border = false;
  for (int y = 0; y < mask.height(); ++y)
    for (int x = 0; x < mask.width(); ++x) {
      const double m = std::clamp(double(mask.at(x, y, 0)), 0.0, 1.0);
      if (m <= 0) continue;
      area += m;
      sx += m * x;
      sy += m * y;
      touches_border |= x == 0 || y == 0 || x == mask.width() - 1 || y == mask.height() - 1;
    }
  if (area < 12) return Status::Error("the sphere mask has no white area (white = sphere)");
  if (touches_border) return Status::Error("the sphere mask touches the image border: the whole sphere must be in view");
  SphereCircle circle;
  circle.centre_px = {sx / area, sy / area};
  circle.radius_px = std::sqrt(area / std::numbers::pi);
  // A disk's second moments are r^2 / 4 about every axis through its centre.
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
  for (int y = 0; y < mask.height(); ++y)
    for (int x = 0; x < mask.width(); ++x) {
      const double m = std::clamp(double(mask.at(x, y, 0)), 0.0, 1.0);
      if (m <= 0) continue;
      const Eigen::Vector2d d = Eigen::Vector2d(x, y) - circle.centre_px;
      cov += m * d * d.transpose();
    }
  cov /= area;
  const Eigen::Vector2d eig = Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(cov).eigenvalues();
  const double expected = circle.radius_px * circle.radius_px / 4;
  if (eig.minCoeff() < 0.9 * expected || eig.maxCoeff() > 1.1 * expected)
    return Status::Error("the sphere mask is not one round disk (second moments " + Fixed(eig(0), 1) + " and " +
                         Fixed(eig(1), 1) + " px^2, a disk of its area has " + Fixed(expected, 1) + ")");
  return circle;
}

Eigen::Vector3d LightFromHighlight(const SphereCircle& sphere, const Eigen::Vector2d& highlight_px,
                                   Eigen::Vector3d* normal) {
  // Image y grows downward, RTI's y upward.
  const double nx = (highlight_px.x() - sphere.centre_px.x()) / sphere.radius_px;
  const double ny = -(highlight_px.y() - sphere.centre_px.y()) / sphere.radius_px;
  const Eigen::Vector3d n(nx, ny, std::sqrt(std::max(0.0, 1 - nx * nx - ny * ny)));
  if (normal) *normal = n;
  const Eigen::Vector3d v = Eigen::Vector3d::UnitZ();
  return (2 * n.dot(v) * n - v).normalized();
}

SphereLight FindSphereLight(const Image& photo, const SphereCircle& sphere, const SphereLightsOptions& options) {
  MESOCAP_CHECK(options.Check().empty(), "FindSphereLight: " + options.Check());
  SphereLight result;
  const Eigen::Vector2d c = sphere.centre_px;
  const double r = sphere.radius_px;
  const int x0 = std::max(0, int(std::floor(c.x() - r))), x1 = std::min(photo.width() - 1, int(std::ceil(c.x() + r)));
  const int y0 = std::max(0, int(std::floor(c.y() - r))), y1 = std::min(photo.height() - 1, int(std::ceil(c.y() + r)));
  if (x0 > x1 || y0 > y1 || r <= 0) {
    result.why_not = "the sphere lies outside this photo";
    return result;
  }
  // Pixels on the outline mix sphere and background: left out.
  const double reach = std::max(r - 1.0, 0.5 * r);
  auto inside = [&](int x, int y) { return (Eigen::Vector2d(x, y) - c).squaredNorm() <= reach * reach; };
  std::vector<float> values;
  float peak = -1;
  int px = 0, py = 0;
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) {
      if (!inside(x, y)) continue;
      const float v = Brightness(photo, x, y);
      values.push_back(v);
      if (v > peak) peak = v, px = x, py = y;
    }
  if (values.size() < 12) {
    result.why_not = "the sphere lies outside this photo";
    return result;
  }
  const double median = UpperMedian(std::move(values));
  result.saturated = peak >= options.saturation;
  if (!result.saturated && peak - median < 0.02) {
    result.why_not = "no highlight: the sphere is dark (brightest point " + Fixed(peak, 4) + ", median " + Fixed(median, 4) +
                     ", linear)";
    return result;
  }
  if (!result.saturated && peak < options.min_peak_over_median * median) {
    result.why_not = "no highlight: the brightest point on the sphere is only " + Fixed(peak / std::max(median, 1e-6), 2) +
                     " times its median (needs " + Fixed(options.min_peak_over_median, 2) + ")";
    return result;
  }
  // The blob around the peak: a clipped plateau's centroid, or the centroid of the excess over
  // the blob level (the highlight's shape, not its clipped top, sets where it is).
  const double level = result.saturated ? options.saturation : median + options.blob_level * (peak - median);
  std::vector<uint8_t> seen(size_t(x1 - x0 + 1) * (y1 - y0 + 1), 0);
  auto mark = [&](int x, int y) -> uint8_t& { return seen[size_t(y - y0) * (x1 - x0 + 1) + (x - x0)]; };
  std::vector<std::pair<int, int>> stack = {{px, py}};
  mark(px, py) = 1;
  double sw = 0, sx = 0, sy = 0, extent = 0;
  int count = 0;
  while (!stack.empty()) {
    const auto [x, y] = stack.back();
    stack.pop_back();
    const double v = Brightness(photo, x, y);
    const double w = result.saturated ? 1.0 : v - level + 1e-6;
    sw += w;
    sx += w * x;
    sy += w * y;
    ++count;
    extent = std::max(extent, std::hypot(x - px, y - py));
    for (auto [dx, dy] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
      const int nx = x + dx, ny = y + dy;
      if (nx < x0 || nx > x1 || ny < y0 || ny > y1 || mark(nx, ny) || !inside(nx, ny)) continue;
      if (Brightness(photo, nx, ny) < level) continue;
      mark(nx, ny) = 1;
      stack.push_back({nx, ny});
    }
  }
  result.blob_pixels = count;
  if (extent > options.max_blob_radius * r) {
    result.why_not = "the bright area around the peak is " + Fixed(extent / r, 2) +
                     " sphere radii across, too large for a mirror highlight (a diffuse or overexposed sphere)";
    return result;
  }
  result.highlight_px = {sx / sw, sy / sw};
  const double rim = (result.highlight_px - c).norm() / r;
  if (rim > options.max_rim_radius) {
    result.why_not = "the highlight is at the rim (" + Fixed(rim, 3) +
                     " radii out): the light is almost behind the sphere, its direction is not reliable";
    return result;
  }
  result.light_dir = LightFromHighlight(sphere, result.highlight_px, &result.normal);
  result.found = true;
  return result;
}

}  // namespace mesocap
