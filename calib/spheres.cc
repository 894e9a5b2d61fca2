#include "calib/spheres.h"

#include <ceres/ceres.h>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>

#include "core/median.h"
#include "core/status.h"

namespace mesocap {
namespace {

// Distance from the sphere centre to an outline ray through the camera centre, minus the radius.
struct TangentCost {
  TangentCost(const Eigen::Vector3d& ray, double radius, double scale = 1) : ray_(ray), radius_(radius), scale_(scale) {}
  template <typename T>
  bool operator()(const T* c, T* residual) const {
    const T along = c[0] * T(ray_.x()) + c[1] * T(ray_.y()) + c[2] * T(ray_.z());
    const T dx = c[0] - along * T(ray_.x()), dy = c[1] - along * T(ray_.y()), dz = c[2] - along * T(ray_.z());
    residual[0] = T(scale_) * (ceres::sqrt(dx * dx + dy * dy + dz * dz) - T(radius_));
    return true;
  }
  Eigen::Vector3d ray_;
  double radius_, scale_;
};

// 8-bit shots are JPEGs, whose chroma is subsampled (blurred over ~2 px) in sRGB-encoded values:
// the halfway point of a blurred edge lies halfway between the encoded levels, and halfway
// between the linear levels sits ~0.4 px inside a coloured ball. sRGB is a power law with an
// affine offset above its toe, and the offset leaves halfway points alone; the power alone is
// scale-free, so a sum of shots serves as well as their mean.
constexpr double kEncodingGamma = 2.4;

// Brightness = the largest colour channel (a blue ball is bright only in blue), one plane.
cv::Mat BrightnessPlane(const Image& im) {
  cv::Mat out(im.height(), im.width(), CV_32F);
  const int channels = std::min(im.channels(), 3);
  for (int y = 0; y < im.height(); ++y)
    for (int x = 0; x < im.width(); ++x) {
      const float* p = im.pixel(x, y);
      out.at<float>(y, x) = *std::max_element(p, p + channels);
    }
  return out;
}

// One channel of `im` inside `roi`, raised to 1 / gamma.
cv::Mat ChannelPlane(const Image& im, int channel, const cv::Rect& roi, double gamma) {
  cv::Mat out(roi.height, roi.width, CV_32F);
  for (int y = 0; y < roi.height; ++y)
    for (int x = 0; x < roi.width; ++x) {
      const float v = std::max(im.at(roi.x + x, roi.y + y, channel), 0.0f);
      out.at<float>(y, x) = gamma == 1 ? v : float(std::pow(v, 1 / gamma));
    }
  return out;
}

// The channel in which the disk (centre, radius) stands out most against the ring around it:
// a plain channel, not the largest per pixel, keeps the grey background's level unbiased by
// noise and by the ball's colour bleeding into it through JPEG's chroma.
int BallChannel(const Image& mean, const Eigen::Vector2d& centre, double radius) {
  const int channels = std::min(mean.channels(), 3);
  std::array<double, 3> in{}, out{};
  int n_in = 0, n_out = 0;
  const int reach = int(std::ceil(1.6 * radius));
  for (int y = std::max(0, int(centre.y()) - reach); y <= std::min(mean.height() - 1, int(centre.y()) + reach); ++y)
    for (int x = std::max(0, int(centre.x()) - reach); x <= std::min(mean.width() - 1, int(centre.x()) + reach); ++x) {
      const double d = std::hypot(x - centre.x(), y - centre.y());
      const bool inside = d < 0.5 * radius, ring = d > 1.3 * radius && d < 1.6 * radius;
      if (!inside && !ring) continue;
      for (int c = 0; c < channels; ++c) (inside ? in : out)[c] += mean.at(x, y, c);
      ++(inside ? n_in : n_out);
    }
  int best = 0;
  double best_ratio = -1;
  for (int c = 0; c < channels; ++c) {
    const double ratio = (in[c] / std::max(n_in, 1)) / std::max(out[c] / std::max(n_out, 1), 1e-9);
    if (ratio > best_ratio) best_ratio = ratio, best = c;
  }
  return best;
}

// Bilinear sample at OpenCV pixel coordinates (pixel centres on integers), clamped.
double Sample(const cv::Mat& plane, double x, double y) {
  x = std::clamp(x, 0.0, double(plane.cols - 1));
  y = std::clamp(y, 0.0, double(plane.rows - 1));
  const int x0 = std::min(int(x), plane.cols - 2), y0 = std::min(int(y), plane.rows - 2);
  const double ax = x - x0, ay = y - y0;
  const float* r0 = plane.ptr<float>(y0) + x0;
  const float* r1 = plane.ptr<float>(y0 + 1) + x0;
  const double top = r0[0] + ax * (r0[1] - r0[0]), bottom = r1[0] + ax * (r1[1] - r1[0]);
  return top + ay * (bottom - top);
}

// Least-squares line a + b * s through (s[i], v[i]) for i in [lo, hi).
struct Line {
  double a = 0, b = 0, rms = 0;
  double At(double s) const { return a + b * s; }
};
Line FitLine(const std::vector<double>& s, const std::vector<double>& v, int lo, int hi) {
  Line line;
  const int n = hi - lo;
  if (n < 2) return line;
  double ms = 0, mv = 0;
  for (int i = lo; i < hi; ++i) ms += s[i], mv += v[i];
  ms /= n;
  mv /= n;
  double sss = 0, ssv = 0;
  for (int i = lo; i < hi; ++i) sss += (s[i] - ms) * (s[i] - ms), ssv += (s[i] - ms) * (v[i] - mv);
  line.b = sss > 0 ? ssv / sss : 0;
  line.a = mv - line.b * ms;
  double sq = 0;
  for (int i = lo; i < hi; ++i) sq += (v[i] - line.At(s[i])) * (v[i] - line.At(s[i]));
  line.rms = std::sqrt(sq / n);
  return line;
}


// The outline of a bright ball on a dark background along one profile from `centre` in unit
// direction `dir`, searched within [s_min, s_max] px of the centre. The edge of an
// anti-aliased (box-filtered) step lies where the profile is halfway between the two sides'
// levels; each level is a straight line fitted beside the ramp and evaluated at the crossing,
// so limb shading and a table darkened by the ball's shadows in some shots do not move it.
// Returns false when the step is not clear (a shadow, a neighbour, a low contrast).
// `gamma`: the plane holds linear values raised to 1 / gamma (1: linear).
bool EdgeAlongProfile(const cv::Mat& plane, double gamma, const Eigen::Vector2d& centre, const Eigen::Vector2d& dir,
                      double s_min, double s_max, double* s_edge, double* level_ratio = nullptr) {
  constexpr double kStep = 0.25;          // px between profile samples
  constexpr double kRamp = 1.5;           // px each side of the edge left to the ramp (box filter + JPEG)
  constexpr double kLevel = 4.0;          // px of each side's level fitted beyond the ramp
  const double lo = s_min - kRamp - kLevel, hi = s_max + kRamp + kLevel;
  std::vector<double> s, v;
  for (double t = lo; t <= hi + 1e-9; t += kStep) {
    s.push_back(t);
    v.push_back(Sample(plane, centre.x() + t * dir.x(), centre.y() + t * dir.y()));
  }
  const int n = int(s.size());
  // Steepest 1 px fall inside the search range.
  const int k = int(std::lround(0.5 / kStep));
  int best = -1;
  double best_drop = 0;
  for (int i = k; i + k < n; ++i) {
    if (s[i] < s_min || s[i] > s_max) continue;
    const double drop = v[i - k] - v[i + k];
    if (drop > best_drop) best_drop = drop, best = i;
  }
  if (best < 0) return false;
  double guess = s[best], ratio = 0;
  for (int iteration = 0; iteration < 2; ++iteration) {
    auto index = [&](double t) { return std::clamp(int(std::lround((t - lo) / kStep)), 0, n - 1); };
    const int in_lo = index(guess - kRamp - kLevel), in_hi = index(guess - kRamp) + 1;
    const int out_lo = index(guess + kRamp), out_hi = index(guess + kRamp + kLevel) + 1;
    const Line inner = FitLine(s, v, in_lo, in_hi), outer = FitLine(s, v, out_lo, out_hi);
    const double contrast = inner.At(guess) - outer.At(guess);
    ratio = inner.At(guess) / std::max(outer.At(guess), 1e-9);
    // A clear step: the ball at least twice as bright as the background, both sides smooth.
    if (contrast <= 0 || inner.At(guess) < std::pow(2.0, 1 / gamma) * outer.At(guess)) return false;
    if (inner.rms > 0.15 * contrast || outer.rms > 0.1 * contrast) return false;
    // The crossing of the profile with the mid-level nearest the guess, inside the ramp.
    double found = NAN, nearest = 1e9;
    for (int i = index(guess - kRamp); i < index(guess + kRamp); ++i) {
      const double g0 = v[i] - 0.5 * (inner.At(s[i]) + outer.At(s[i]));
      const double g1 = v[i + 1] - 0.5 * (inner.At(s[i + 1]) + outer.At(s[i + 1]));
      if (g0 >= 0 && g1 < 0) {
        const double t = s[i] + kStep * g0 / (g0 - g1);
        if (std::abs(t - guess) < nearest) nearest = std::abs(t - guess), found = t;
      }
    }
    if (std::isnan(found)) return false;
    guess = found;
  }
  if (guess < s_min || guess > s_max) return false;
  *s_edge = guess;
  if (level_ratio) *level_ratio = std::pow(ratio, gamma);
  return true;
}

// Outline points of the ball around `centre` (about `radius` px) at `n_rays` angles; rays where
// the step is not clear are skipped. `weights` (optional): each point's squared step height in
// the plane's values, the precision of its position up to a common factor.
std::vector<Eigen::Vector2d> MeasureOutline(const cv::Mat& plane, double gamma, const Eigen::Vector2d& centre,
                                            double radius, double search_px, int n_rays,
                                            std::vector<double>* weights = nullptr) {
  std::vector<Eigen::Vector2d> points;
  if (weights) weights->clear();
  for (int k = 0; k < n_rays; ++k) {
    const double a = 2 * std::numbers::pi * k / n_rays;
    const Eigen::Vector2d dir(std::cos(a), std::sin(a));
    double s = 0, ratio = 0;
    if (!EdgeAlongProfile(plane, gamma, centre, dir, radius - search_px, radius + search_px, &s, &ratio)) continue;
    points.push_back(centre + s * dir);
    if (weights) weights->push_back(std::pow(std::pow(ratio, 1 / gamma) - 1, 2));
  }
  return points;
}

// A circle through most of `points` with a radius in [r_min, r_max] (RANSAC, deterministic):
// the outline found around a poor first guess, where a crescent-shaped blob misplaced it.
bool RobustCircle(const std::vector<Eigen::Vector2d>& points, double r_min, double r_max, Eigen::Vector2d* centre,
                  double* radius) {
  if (points.size() < 3) return false;
  std::mt19937 rng(12345);
  std::uniform_int_distribution<size_t> pick(0, points.size() - 1);
  size_t best_inliers = 0;
  for (int it = 0; it < 400; ++it) {
    const Eigen::Vector2d &a = points[pick(rng)], &b = points[pick(rng)], &c = points[pick(rng)];
    // Circumcentre of a, b, c.
    const double d = 2 * (a.x() * (b.y() - c.y()) + b.x() * (c.y() - a.y()) + c.x() * (a.y() - b.y()));
    if (std::abs(d) < 1e-6) continue;
    const Eigen::Vector2d o((a.squaredNorm() * (b.y() - c.y()) + b.squaredNorm() * (c.y() - a.y()) + c.squaredNorm() * (a.y() - b.y())) / d,
                            (a.squaredNorm() * (c.x() - b.x()) + b.squaredNorm() * (a.x() - c.x()) + c.squaredNorm() * (b.x() - a.x())) / d);
    const double r = (a - o).norm();
    if (r < r_min || r > r_max) continue;
    size_t inliers = 0;
    for (const auto& p : points) inliers += std::abs((p - o).norm() - r) < 1.5;
    if (inliers > best_inliers) best_inliers = inliers, *centre = o, *radius = r;
  }
  return best_inliers >= 8;
}

// Algebraic circle fit (Kasa), then geometric Gauss-Newton steps; false if degenerate.
bool FitCircle(const std::vector<Eigen::Vector2d>& points, Eigen::Vector2d* centre, double* radius, double* rms) {
  if (points.size() < 3) return false;
  Eigen::MatrixXd A(points.size(), 3);
  Eigen::VectorXd b(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    A(i, 0) = points[i].x();
    A(i, 1) = points[i].y();
    A(i, 2) = 1;
    b(i) = points[i].squaredNorm();
  }
  const Eigen::Vector3d x = A.colPivHouseholderQr().solve(b);
  Eigen::Vector2d c(x(0) / 2, x(1) / 2);
  double r2 = x(2) + c.squaredNorm();
  if (!(r2 > 0)) return false;
  double r = std::sqrt(r2);
  for (int it = 0; it < 5; ++it) {
    Eigen::Matrix3d JtJ = Eigen::Matrix3d::Zero();
    Eigen::Vector3d Jtr = Eigen::Vector3d::Zero();
    for (const auto& p : points) {
      const Eigen::Vector2d d = p - c;
      const double dist = d.norm();
      if (dist < 1e-9) continue;
      const Eigen::Vector3d J(-d.x() / dist, -d.y() / dist, -1);
      JtJ += J * J.transpose();
      Jtr += J * (dist - r);
    }
    const Eigen::Vector3d delta = JtJ.ldlt().solve(-Jtr);
    if (!delta.allFinite()) return false;
    c += delta.head<2>();
    r += delta(2);
  }
  double sq = 0;
  for (const auto& p : points) sq += ((p - c).norm() - r) * ((p - c).norm() - r);
  *centre = c;
  *radius = r;
  *rms = std::sqrt(sq / points.size());
  return std::isfinite(r) && r > 0;
}

}  // namespace

std::string SphereOptions::Check() const {
  if (!(radius_m > 0)) return "sphere radius must be positive";
  if (!(min_ball_to_background > 1)) return "a ball must be brighter than its background (ratio > 1)";
  if (expected_count < 1) return "expected sphere count must be at least 1";
  if (!(min_circularity > 0 && min_circularity <= 1)) return "min circularity must be in (0, 1]";
  if (n_rays < 36) return "at least 36 outline rays";
  if (!(min_outline_fraction > 0 && min_outline_fraction <= 1)) return "min outline fraction must be in (0, 1]";
  return "";
}

Json SphereEstimate::ToJson() const {
  return {{"center_m", mesocap::ToJson(center_m)}, {"radius_m", radius_m},
          {"image_centre_px", mesocap::ToJson(image_centre_px)}, {"image_radius_px", image_radius_px},
          {"outline_points", outline_points}, {"rms_tangent_error_mm", rms_tangent_error_mm}};
}

SphereReport LocateSpheres(const CameraModel& camera, const Image& max_image, const Image& mean_image,
                           const SphereOptions& options) {
  MESOCAP_CHECK(options.Check().empty(), "LocateSpheres: " + options.Check());
  MESOCAP_CHECK(max_image.size() == mean_image.size() && !max_image.empty(), "LocateSpheres: max and mean images differ in size");
  SphereReport report;
  const int W = max_image.width(), H = max_image.height();
  // The camera is about 1 m from the table, the balls anywhere in a wide frame.
  const double expected_radius_px = camera.K(0, 0) * options.radius_m / 1.0;
  const double gamma = options.outline_encoded ? kEncodingGamma : 1.0;

  // Candidates: blobs in the per-pixel maximum well above the local background. A flash close
  // to the table lights it brighter than a distant flash lights a ball, so the background is a
  // median over about three ball diameters (on a 4x smaller image, in 8-bit encoded values).
  constexpr int kShrink = 4;
  cv::Mat small;
  cv::resize(BrightnessPlane(max_image), small, {W / kShrink, H / kShrink}, 0, 0, cv::INTER_AREA);
  double peak = 0;
  cv::minMaxLoc(small, nullptr, &peak);
  peak = std::max(peak, 1e-6);
  cv::Mat encoded8(small.size(), CV_8U), background8;
  for (int y = 0; y < small.rows; ++y)
    for (int x = 0; x < small.cols; ++x)
      encoded8.at<uint8_t>(y, x) = cv::saturate_cast<uint8_t>(255 * std::sqrt(small.at<float>(y, x) / peak));
  const int window = 2 * int(3 * expected_radius_px / kShrink) + 1;
  cv::medianBlur(encoded8, background8, std::max(window, 5));
  cv::Mat mask(small.size(), CV_8U);
  for (int y = 0; y < small.rows; ++y)
    for (int x = 0; x < small.cols; ++x) {
      const double bg = peak * std::pow((background8.at<uint8_t>(y, x) + 0.5) / 255.0, 2);
      mask.at<uint8_t>(y, x) = small.at<float>(y, x) > options.min_ball_to_background * bg ? 255 : 0;
    }
  cv::morphologyEx(mask, mask, cv::MORPH_OPEN, cv::getStructuringElement(cv::MORPH_ELLIPSE, {3, 3}));
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(mask, contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE);

  auto where = [](const Eigen::Vector2d& c) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "(%.0f, %.0f)", c.x(), c.y());
    return std::string(buf);
  };
  struct Candidate {
    SphereEstimate estimate;
    double quality;  // fraction of outline rays measured
  };
  std::vector<Candidate> candidates;
  for (const auto& raw_contour : contours) {
    // The convex hull bridges a dim crescent on the ball's unlit side.
    std::vector<cv::Point> contour;
    cv::convexHull(raw_contour, contour);
    cv::Point2f cf;
    float rf;
    cv::minEnclosingCircle(contour, cf, rf);
    const double circularity = cv::contourArea(contour) / (std::numbers::pi * rf * rf);
    // Small-image pixel i covers full-size pixels kShrink * i .. kShrink * i + kShrink - 1.
    const Eigen::Vector2d blob_centre(kShrink * cf.x + 0.5 * (kShrink - 1), kShrink * cf.y + 0.5 * (kShrink - 1));
    const double blob_radius = kShrink * (rf + 0.5);
    if (blob_radius < 0.5 * expected_radius_px || blob_radius > 1.6 * expected_radius_px) continue;
    if (circularity < options.min_circularity) {
      if (circularity > 0.5)
        report.rejected_blobs.push_back("blob at " + where(blob_centre) + " not round enough (circularity " +
                                        std::to_string(circularity) + ")");
      continue;
    }
    const int ball_channel = BallChannel(mean_image, blob_centre, blob_radius);
    const int margin = int(std::ceil(0.6 * blob_radius)) + 20;
    const cv::Rect roi = cv::Rect(int(blob_centre.x() - blob_radius) - margin, int(blob_centre.y() - blob_radius) - margin,
                                  int(2 * blob_radius) + 2 * margin, int(2 * blob_radius) + 2 * margin) &
                         cv::Rect(0, 0, W, H);
    const cv::Mat mean_plane = ChannelPlane(mean_image, ball_channel, roi, gamma);
    const Eigen::Vector2d offset(roi.x, roi.y);
    auto measure = [&](const Eigen::Vector2d& centre, double radius, double search_px,
                       std::vector<double>* weights = nullptr) {
      std::vector<Eigen::Vector2d> points =
          MeasureOutline(mean_plane, gamma, centre - offset, radius, search_px, options.n_rays, weights);
      for (auto& p : points) p += offset;
      return points;
    };
    // Outline in the mean image: a coarse pass around the blob's circle and a robust circle
    // through it (a blob missing a dim side is smaller than the ball and off its centre), then
    // fine passes around the circle fitted to the previous pass.
    Eigen::Vector2d c = blob_centre;
    double r = blob_radius, rms_px = 0;
    std::vector<Eigen::Vector2d> outline = measure(c, r, 0.5 * r);
    if (!RobustCircle(outline, 0.6 * expected_radius_px, 1.5 * expected_radius_px, &c, &r)) outline.clear();
    else outline = measure(c, r, 4.0);
    // Two rounds: fit a circle, drop points far off it (a neighbour, a shadow edge), refit, and
    // measure again around it; +-4 px holds the perspective ellipse around its best circle (~3 px
    // apart at the frame's edge). The last measurement is kept whole: the 3D fit judges it.
    bool fitted = false;
    std::vector<double> weights;
    for (int round = 0; round < 2 && outline.size() >= 8; ++round) {
      if (!FitCircle(outline, &c, &r, &rms_px)) break;
      std::vector<Eigen::Vector2d> kept;
      for (const auto& p : outline)
        if (std::abs((p - c).norm() - r) < std::max(1.0, 3 * rms_px)) kept.push_back(p);
      if (kept.size() < 8 || !FitCircle(kept, &c, &r, &rms_px)) break;
      outline = measure(c, r, 4.0, &weights);
      fitted = round == 1;
    }
    const double fraction = double(outline.size()) / options.n_rays;
    if (!fitted || fraction < options.min_outline_fraction) {
      report.rejected_blobs.push_back("round blob at " + where(blob_centre) + ": a ball's outline clear on only " +
                                      std::to_string(int(std::lround(100 * fraction))) + "% of its sides");
      continue;
    }
    // Undistorted rays through the outline; the 3D fit below models the perspective ellipse, and
    // its robust loss and outlier pass judge the points, not the circle.
    std::vector<Eigen::Vector3d> rays;
    for (const auto& p : outline) rays.push_back(camera.PixelToRay(p));
    double mean_weight = 0;
    for (double w : weights) mean_weight += w / weights.size();
    for (double& w : weights) w = std::sqrt(w / mean_weight);  // residual scale: sqrt(precision)
    // Initial centre: along the mean outline direction, at the depth the cone's angle implies.
    Eigen::Vector3d axis = Eigen::Vector3d::Zero();
    for (const auto& d : rays) axis += d;
    axis.normalize();
    double mean_angle = 0;
    for (const auto& d : rays) mean_angle += std::acos(std::clamp(d.dot(axis), -1.0, 1.0));
    mean_angle /= rays.size();
    const Eigen::Vector3d init = axis * (options.radius_m / std::sin(mean_angle));
    double centre[3] = {init.x(), init.y(), init.z()};
    // Each ray's tangent distance, weighted by its step's height (a faint step is blurred more
    // by JPEG's chroma, relative to its height, and sits slightly inside), robustly: about
    // 0.1 px of outline noise is 0.03 mm at 1 m.
    auto solve = [&](const std::vector<Eigen::Vector3d>& use, const std::vector<double>& scale) {
      ceres::Problem problem;
      for (size_t i = 0; i < use.size(); ++i)
        problem.AddResidualBlock(
            new ceres::AutoDiffCostFunction<TangentCost, 1, 3>(new TangentCost(use[i], options.radius_m, scale[i])),
            new ceres::CauchyLoss(0.0002), centre);
      ceres::Solver::Options solver;
      solver.linear_solver_type = ceres::DENSE_QR;
      solver.function_tolerance = 1e-12;
      solver.parameter_tolerance = 1e-12;
      ceres::Solver::Summary summary;
      ceres::Solve(solver, &problem, &summary);
    };
    auto tangent_error = [&](const Eigen::Vector3d& d) {
      const Eigen::Vector3d cc(centre[0], centre[1], centre[2]);
      return (cc - cc.dot(d) * d).norm() - options.radius_m;
    };
    solve(rays, weights);
    // Drop rays more than 3 robust sigmas off, solve again.
    std::vector<double> abs_err;
    for (const auto& d : rays) abs_err.push_back(std::abs(tangent_error(d)));
    const double sigma = std::max(1.4826 * UpperMedian(abs_err), 1e-5);
    std::vector<Eigen::Vector3d> inliers;
    std::vector<double> inlier_weights;
    for (size_t i = 0; i < rays.size(); ++i)
      if (abs_err[i] < 3 * sigma) inliers.push_back(rays[i]), inlier_weights.push_back(weights[i]);
    if (inliers.size() >= 8 && inliers.size() < rays.size()) {
      rays = inliers;
      weights = inlier_weights;
      solve(rays, weights);
    }
    SphereEstimate s;
    s.center_m = {centre[0], centre[1], centre[2]};
    s.radius_m = options.radius_m;
    s.image_centre_px = camera.Project(s.center_m);
    s.image_radius_px = r;
    s.outline_points = int(rays.size());
    double sq = 0;
    for (const auto& d : rays) sq += tangent_error(d) * tangent_error(d);
    s.rms_tangent_error_mm = 1000 * std::sqrt(sq / rays.size());
    if (!s.center_m.allFinite() || s.center_m.z() <= options.radius_m) {
      report.rejected_blobs.push_back("ball at " + where(blob_centre) + ": the tangent rays do not meet a ball of the known radius");
      continue;
    }
    candidates.push_back({s, fraction});
  }
  // More round bright things than balls: keep the ones with the most complete outlines.
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const Candidate& a, const Candidate& b) { return a.quality > b.quality; });
  for (size_t i = 0; i < candidates.size(); ++i) {
    if (int(i) < options.expected_count) report.spheres.push_back(candidates[i].estimate);
    else
      report.rejected_blobs.push_back("ball-like blob at " + where(candidates[i].estimate.image_centre_px) +
                                      ": more candidates than the " + std::to_string(options.expected_count) +
                                      " expected balls, and its outline is the least complete");
  }
  std::sort(report.spheres.begin(), report.spheres.end(), [](const SphereEstimate& a, const SphereEstimate& b) {
    return a.image_centre_px.x() != b.image_centre_px.x() ? a.image_centre_px.x() < b.image_centre_px.x()
                                                          : a.image_centre_px.y() < b.image_centre_px.y();
  });
  return report;
}

}  // namespace mesocap
