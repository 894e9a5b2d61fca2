#include "calib/spheres.h"

#include <ceres/ceres.h>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace mesocap {
namespace {

// Distance from the sphere centre to an outline ray through the camera centre, minus the radius.
struct TangentCost {
  TangentCost(const Eigen::Vector3d& ray, double radius) : ray_(ray), radius_(radius) {}
  template <typename T>
  bool operator()(const T* c, T* residual) const {
    const T along = c[0] * T(ray_.x()) + c[1] * T(ray_.y()) + c[2] * T(ray_.z());
    const T dx = c[0] - along * T(ray_.x()), dy = c[1] - along * T(ray_.y()), dz = c[2] - along * T(ray_.z());
    residual[0] = ceres::sqrt(dx * dx + dy * dy + dz * dz) - T(radius_);
    return true;
  }
  Eigen::Vector3d ray_;
  double radius_;
};

float BrightnessAt(const Image& im, double x, double y) {
  float px[4] = {0, 0, 0, 0};
  im.SampleBilinear(float(x + 0.5), float(y + 0.5), px);  // OpenCV pixel convention -> Image's
  return *std::max_element(px, px + std::min(im.channels(), 3));
}

}  // namespace

Json SphereEstimate::ToJson() const {
  return {{"center_m", mesocap::ToJson(center_m)}, {"radius_m", radius_m},
          {"image_centre_px", mesocap::ToJson(image_centre_px)}, {"image_radius_px", image_radius_px},
          {"outline_points", outline_points}, {"rms_tangent_error_mm", rms_tangent_error_mm}};
}

SphereReport LocateSpheres(const CameraModel& camera, const Image& max_image, const Image& mean_image,
                           const SphereOptions& options) {
  SphereReport report;
  const int W = max_image.width(), H = max_image.height();
  // Brightness = the largest channel (a blue ball is bright only in blue).
  cv::Mat bright(H, W, CV_32F);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const float* p = max_image.pixel(x, y);
      bright.at<float>(y, x) = *std::max_element(p, p + std::min(max_image.channels(), 3));
    }
  // The dark table fills most of the frame: threshold well above its median.
  std::vector<float> sample;
  for (int i = 0; i < W * H; i += 61) sample.push_back(bright.at<float>(i / W, i % W));
  std::nth_element(sample.begin(), sample.begin() + sample.size() / 2, sample.end());
  const float threshold = 2.0f * sample[sample.size() / 2];
  cv::Mat mask = bright > threshold;
  cv::morphologyEx(mask, mask, cv::MORPH_OPEN, cv::getStructuringElement(cv::MORPH_ELLIPSE, {5, 5}));
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(mask, contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE);

  const double expected_radius_px = camera.K(0, 0) * options.radius_m / 1.0;  // at about 1 m
  for (const auto& raw_contour : contours) {
    // The convex hull bridges a dim crescent on the ball's unlit side.
    std::vector<cv::Point> contour;
    cv::convexHull(raw_contour, contour);
    cv::Point2f c;
    float r;
    cv::minEnclosingCircle(contour, c, r);
    if (r < 0.5 * expected_radius_px || r > 1.6 * expected_radius_px) continue;
    const double circularity = cv::contourArea(contour) / (std::numbers::pi * r * r);
    if (circularity < options.min_circularity) {
      if (circularity > 0.7)
        report.rejected_blobs.push_back("blob at (" + std::to_string(int(c.x)) + ", " + std::to_string(int(c.y)) +
                                        ") not round enough (circularity " + std::to_string(circularity) + ")");
      continue;
    }
    // Sub-pixel outline: along rays from the blob centre, the centroid of the profile's drop.
    // A pixel-box-filtered step has a flat-topped derivative, so its argmax is ill-defined and
    // any limb shading tilts it inward; the centroid, with the shading slope removed, is not.
    std::vector<Eigen::Vector3d> rays;
    const int n_rays = 360;
    const double step = 0.25;
    for (int k = 0; k < n_rays; ++k) {
      const double a = 2 * std::numbers::pi * k / n_rays, dx = std::cos(a), dy = std::sin(a);
      const double inner = BrightnessAt(mean_image, c.x + (r - 6) * dx, c.y + (r - 6) * dy);
      const double outer = BrightnessAt(mean_image, c.x + (r + 6) * dx, c.y + (r + 6) * dy);
      if (inner < 2 * outer) continue;  // a shadow or a neighbour spoils this side
      std::vector<double> profile;
      for (double s = r - 8; s <= r + 8; s += step) profile.push_back(BrightnessAt(mean_image, c.x + s * dx, c.y + s * dy));
      std::vector<double> drop(profile.size() - 1);
      for (size_t i = 0; i + 1 < profile.size(); ++i) drop[i] = profile[i] - profile[i + 1];
      const int best = int(std::max_element(drop.begin(), drop.end()) - drop.begin());
      const int half = 10;  // 2.5 px each side
      if (best < half || best + half >= int(drop.size())) continue;
      const double base = 0.5 * (drop[best - half] + drop[best + half]);
      double sw = 0, si = 0;
      for (int i = best - half; i <= best + half; ++i) {
        const double w = std::max(0.0, drop[i] - base);
        sw += w;
        si += w * i;
      }
      if (sw < 0.3 * (inner - outer)) continue;
      const double found = r - 8 + (si / sw + 0.5) * step;
      rays.push_back(camera.PixelToRay({c.x + found * dx, c.y + found * dy}));
    }
    if (rays.size() < 60) {
      report.rejected_blobs.push_back("ball at (" + std::to_string(int(c.x)) + ", " + std::to_string(int(c.y)) +
                                      "): outline not clear on enough sides");
      continue;
    }
    // Initial centre: along the mean outline direction, at the depth the cone's angle implies.
    Eigen::Vector3d axis = Eigen::Vector3d::Zero();
    for (const auto& d : rays) axis += d;
    axis.normalize();
    double mean_angle = 0;
    for (const auto& d : rays) mean_angle += std::acos(std::clamp(d.dot(axis), -1.0, 1.0));
    mean_angle /= rays.size();
    double centre[3];
    const Eigen::Vector3d init = axis * (options.radius_m / std::sin(mean_angle));
    for (int i = 0; i < 3; ++i) centre[i] = init[i];
    ceres::Problem problem;
    for (const auto& d : rays)
      problem.AddResidualBlock(new ceres::AutoDiffCostFunction<TangentCost, 1, 3>(new TangentCost(d, options.radius_m)),
                               new ceres::HuberLoss(0.0005), centre);
    ceres::Solver::Options solver;
    solver.linear_solver_type = ceres::DENSE_QR;
    ceres::Solver::Summary summary;
    ceres::Solve(solver, &problem, &summary);
    SphereEstimate s;
    s.center_m = {centre[0], centre[1], centre[2]};
    s.radius_m = options.radius_m;
    s.image_centre_px = camera.Project(s.center_m);
    s.image_radius_px = r;
    s.outline_points = int(rays.size());
    double sq = 0;
    for (const auto& d : rays) {
      const double dist = (s.center_m - s.center_m.dot(d) * d).norm() - options.radius_m;
      sq += dist * dist;
    }
    s.rms_tangent_error_mm = 1000 * std::sqrt(sq / rays.size());
    report.spheres.push_back(s);
  }
  std::sort(report.spheres.begin(), report.spheres.end(), [](const SphereEstimate& a, const SphereEstimate& b) {
    return a.image_centre_px.x() != b.image_centre_px.x() ? a.image_centre_px.x() < b.image_centre_px.x()
                                                          : a.image_centre_px.y() < b.image_centre_px.y();
  });
  return report;
}

}  // namespace mesocap
