#include "calib/intrinsics.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <memory>
#include <mutex>

#include <ceres/ceres.h>
#include <ceres/covariance.h>
#include <ceres/rotation.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "calib/intrinsics_cost.h"
#include "core/image_io.h"
#include "core/image_u8_io.h"
#include "core/parallel.h"
#include "core/progress.h"
#include "core/text_format.h"

namespace mesocap {
namespace {

using Clock = std::chrono::steady_clock;

std::string PatternName(const IntrinsicsOptions& o) { return std::to_string(o.cols) + "x" + std::to_string(o.rows); }

double Median(std::vector<double> v) {
  if (v.empty()) return 0;
  const size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + mid, v.end());
  double m = v[mid];
  if (v.size() % 2 == 0) m = 0.5 * (m + *std::max_element(v.begin(), v.begin() + mid));
  return m;
}

// 8-bit grey for the detectors. 8-bit files hold sRGB values (read with linearize=false); 16-bit
// and float files hold linear values, which are sRGB-encoded first so the detectors see the
// contrast they were tuned for.
cv::Mat ToGray8(const Image& image, bool linear_values) {
  cv::Mat gray;
  const cv::Mat m = image.AsMat();
  switch (image.channels()) {
    case 1: gray = m.clone(); break;
    case 3: cv::cvtColor(m, gray, cv::COLOR_RGB2GRAY); break;
    case 4: cv::cvtColor(m, gray, cv::COLOR_RGBA2GRAY); break;
    default: cv::extractChannel(m, gray, 0); break;
  }
  if (linear_values) {
    for (int y = 0; y < gray.rows; ++y) {
      float* row = gray.ptr<float>(y);
      for (int x = 0; x < gray.cols; ++x) row[x] = LinearToSrgb(std::clamp(row[x], 0.0f, 1.0f));
    }
  }
  cv::Mat gray8;
  gray.convertTo(gray8, CV_8U, 255.0);
  return gray8;
}

// cv::cornerSubPix with a half window of 0.3 x the smallest spacing between neighbouring corners:
// scaled to the squares in pixels, so it behaves alike at any resolution. Wider windows take in
// the outer edges of the border squares on tilted views (on OpenCV's own left/right photos the
// worst image's RMS jumps from 0.24 px at 0.35 x to 0.49 px at 0.38 x and 1.8 px at 0.46 x, the
// previous rule); 0.3 keeps a margin below that. Measured against OpenCV's reference procedure
// (its calibration sample: a fixed 11x11 window) on those photos: RMS 0.18/0.19 px against
// 0.41/0.46 px, and lower error on held-out images and steadier stereo poses.
void RefineSubPix(const cv::Mat& gray, const IntrinsicsOptions& o, std::vector<cv::Point2f>* corners) {
  const auto& c = *corners;
  double spacing = std::numeric_limits<double>::max();
  for (int r = 0; r < o.rows; ++r)
    for (int k = 0; k + 1 < o.cols; ++k)
      spacing = std::min(spacing, double(cv::norm(c[r * o.cols + k + 1] - c[r * o.cols + k])));
  for (int r = 0; r + 1 < o.rows; ++r)
    for (int k = 0; k < o.cols; ++k)
      spacing = std::min(spacing, double(cv::norm(c[(r + 1) * o.cols + k] - c[r * o.cols + k])));
  const int half = std::max(2, int(std::lround(0.3 * spacing)));
  cv::cornerSubPix(gray, *corners, cv::Size(half, half), cv::Size(-1, -1),
                   cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 100, 1e-4));
}

// The photo as 8-bit grey: an 8-bit file decoded straight to grey (a JPEG's luma, without its
// colour: a third of the decoding), anything else read whole and converted. Empty with
// im->reason set when unreadable.
cv::Mat ReadGray8(IntrinsicsImage* im) {
  if (auto grey = ReadImageU8(im->file, 1); grey.ok())
    return cv::Mat(grey->height(), grey->width(), CV_8UC1, grey->data()).clone();
  ImageInfo info;
  auto image = ReadImage(im->file, {.linearize = false, .max_channels = 4}, &info);
  if (!image.ok()) {
    // The status names the file already; the report lists the file beside the reason.
    std::string why = image.status().message();
    const std::string prefix = im->file.string() + ": ";
    if (why.starts_with(prefix)) why = why.substr(prefix.size());
    im->reason = "unreadable: " + why;
    return {};
  }
  return ToGray8(*image, info.bits_per_sample > 8);
}

// Reads one image and finds the board's inner corners; fills corners_px, detector, edge_rise_px
// or reason. `size` gets the image size when the file could be read.
void DetectCorners(const IntrinsicsOptions& o, IntrinsicsImage* im, cv::Size* size) {
  try {
    const cv::Mat gray = ReadGray8(im);
    if (gray.empty()) return;
    *size = gray.size();
    const cv::Size pattern(o.cols, o.rows);
    std::vector<cv::Point2f> corners;
    bool found = false;
    if (o.refinement == CornerRefinement::kSbAccuracy) {
      found = cv::findChessboardCornersSB(gray, pattern, corners, cv::CALIB_CB_ACCURACY | cv::CALIB_CB_NORMALIZE_IMAGE);
      im->detector = "sb-accuracy";
    } else {
      const double scale = std::min(1.0, double(o.max_detect_side_px) / std::max(gray.cols, gray.rows));
      cv::Mat small = gray;
      if (scale < 1) cv::resize(gray, small, cv::Size(), scale, scale, cv::INTER_AREA);
      found = cv::findChessboardCornersSB(small, pattern, corners, cv::CALIB_CB_NORMALIZE_IMAGE);
      if (found) {
        // Pixel centres at integers on both grids: x_full + 0.5 = (x_small + 0.5) / scale.
        for (auto& p : corners) p = (p + cv::Point2f(0.5f, 0.5f)) * float(1 / scale) - cv::Point2f(0.5f, 0.5f);
        RefineSubPix(gray, o, &corners);
        im->detector = "sb+subpix";
      }
    }
    if (!found) {
      corners.clear();
      found = cv::findChessboardCorners(gray, pattern, corners,
                                        cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE |
                                            cv::CALIB_CB_FAST_CHECK);
      if (found) {
        RefineSubPix(gray, o, &corners);
        im->detector = "classic+subpix";
      }
    }
    if (!found || int(corners.size()) != o.cols * o.rows) {
      im->detector.clear();
      im->reason = "no " + PatternName(o) + " checkerboard found";
      return;
    }
    im->corners_px.reserve(corners.size());
    for (const auto& p : corners) im->corners_px.emplace_back(p.x, p.y);
    const cv::Scalar sharpness = cv::estimateChessboardSharpness(gray, pattern, corners);
    im->edge_rise_px = sharpness[0];
  } catch (const cv::Exception& e) {
    im->corners_px.clear();
    im->reason = std::string("corner detection failed: ") + e.what();
  }
}

struct SolveOutput {
  int iterations = 0;
  std::string summary;
  bool covariance_ok = false;
  Eigen::Matrix<double, kNumIntrinsics, kNumIntrinsics> covariance;  // unit-variance residuals
};

// One Ceres solve over the images in `active` (shared intrinsics, one pose each).
SolveOutput SolveOnce(const IntrinsicsOptions& o, const std::vector<Eigen::Vector3d>& board,
                      const std::vector<IntrinsicsImage>& images, const std::vector<int>& active,
                      double* intrinsics, std::vector<std::array<double, kNumPoseParams>>* poses,
                      bool want_covariance) {
  std::unique_ptr<ceres::LossFunction> loss;
  if (o.loss == RobustLoss::kHuber) loss = std::make_unique<ceres::HuberLoss>(o.loss_scale_px);
  if (o.loss == RobustLoss::kCauchy) loss = std::make_unique<ceres::CauchyLoss>(o.loss_scale_px);
  ceres::Problem::Options problem_options;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  for (const int i : active) {
    for (size_t j = 0; j < board.size(); ++j)
      problem.AddResidualBlock(CheckerboardReprojectionCost::Create(images[i].corners_px[j], board[j]), loss.get(),
                               intrinsics, (*poses)[i].data());
  }
  ceres::Solver::Options so;
  so.linear_solver_type = ceres::DENSE_SCHUR;
  so.max_num_iterations = o.max_iterations;
  so.function_tolerance = 1e-12;
  so.gradient_tolerance = 1e-14;
  so.parameter_tolerance = 1e-12;
  // One thread: the solve takes ~0.1 s, and a parallel Schur complement would sum in an order
  // that depends on the thread count (results must not).
  so.num_threads = 1;
  so.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);

  SolveOutput out;
  out.iterations = int(summary.iterations.size());
  out.summary = summary.BriefReport();
  if (want_covariance) {
    ceres::Covariance::Options co;
    const int num_params = kNumIntrinsics + kNumPoseParams * int(active.size());
    co.algorithm_type = num_params <= 3000 ? ceres::DENSE_SVD : ceres::SPARSE_QR;
    co.num_threads = so.num_threads;
    ceres::Covariance covariance(co);
    std::vector<std::pair<const double*, const double*>> blocks = {{intrinsics, intrinsics}};
    if (covariance.Compute(blocks, &problem)) {
      // Ceres fills a row-major block.
      Eigen::Matrix<double, kNumIntrinsics, kNumIntrinsics, Eigen::RowMajor> c;
      out.covariance_ok = covariance.GetCovarianceBlock(intrinsics, intrinsics, c.data());
      out.covariance = c;
    }
  }
  return out;
}

// Plain (not robustified) residuals of one image under the current estimate.
void EvaluateImage(const std::vector<Eigen::Vector3d>& board, const double* intrinsics, const double* pose,
                   IntrinsicsImage* im) {
  im->residuals_px.resize(board.size());
  double sum2 = 0, max_error = 0;
  for (size_t j = 0; j < board.size(); ++j) {
    const CheckerboardReprojectionCost cost(im->corners_px[j], board[j]);
    double r[2];
    cost(intrinsics, pose, r);
    im->residuals_px[j] = {r[0], r[1]};
    const double e2 = r[0] * r[0] + r[1] * r[1];
    sum2 += e2;
    max_error = std::max(max_error, std::sqrt(e2));
  }
  im->rms_px = std::sqrt(sum2 / double(board.size()));
  im->max_error_px = max_error;
  Eigen::Matrix3d R;
  ceres::AngleAxisToRotationMatrix(pose, R.data());  // column-major, as Eigen stores it
  im->cam_from_board_R = R;
  im->cam_from_board_t = Eigen::Vector3d(pose[3], pose[4], pose[5]);
}

}  // namespace

std::string RobustLossToString(RobustLoss loss) {
  switch (loss) {
    case RobustLoss::kNone: return "none";
    case RobustLoss::kHuber: return "huber";
    case RobustLoss::kCauchy: return "cauchy";
  }
  return "unknown";
}

bool StringToRobustLoss(const std::string& s, RobustLoss* loss) {
  for (RobustLoss l : {RobustLoss::kNone, RobustLoss::kHuber, RobustLoss::kCauchy}) {
    if (s == RobustLossToString(l)) {
      *loss = l;
      return true;
    }
  }
  return false;
}

std::string CornerRefinementToString(CornerRefinement r) {
  return r == CornerRefinement::kSbAccuracy ? "sb-accuracy" : "subpix";
}

bool StringToCornerRefinement(const std::string& s, CornerRefinement* r) {
  for (CornerRefinement c : {CornerRefinement::kSubPix, CornerRefinement::kSbAccuracy}) {
    if (s == CornerRefinementToString(c)) {
      *r = c;
      return true;
    }
  }
  return false;
}

std::string IntrinsicsOptions::Check() const {
  if (cols < 2 || rows < 2) return "the board needs at least 2x2 inner corners, not " + PatternName(*this);
  if (cols == rows)
    return "a square board (" + PatternName(*this) + ") is ambiguous under rotation; use one with cols != rows";
  if (!(square_m > 0) || !std::isfinite(square_m)) return "the square size must be positive (metres)";
  if (max_detect_side_px < 200) return "the detection size must be at least 200 px";
  if (!(loss_scale_px > 0)) return "the robust loss scale must be positive (px)";
  if (!(outlier_rms_factor > 1)) return "the outlier RMS factor must be above 1";
  if (blur_median_factor < 1) return "the blur factor must be at least 1";
  if (outlier_min_rms_px < 0) return "the outlier RMS floor must not be negative";
  if (max_outlier_rounds < 0) return "the number of outlier rounds must not be negative";
  if (min_images < 1) return "at least 1 image must be required";
  if (max_iterations < 1) return "the solver needs at least 1 iteration";
  if (num_threads == 0 || num_threads < -1) return "num_threads must be -1 (all cores) or positive";
  return "";
}

Json IntrinsicsOptions::ToJson() const {
  return {{"cols", cols},
          {"rows", rows},
          {"square_m", square_m},
          {"refinement", CornerRefinementToString(refinement)},
          {"max_detect_side_px", max_detect_side_px},
          {"loss", RobustLossToString(loss)},
          {"loss_scale_px", loss_scale_px},
          {"outlier_rms_factor", outlier_rms_factor},
          {"outlier_min_rms_px", outlier_min_rms_px},
          {"max_outlier_rounds", max_outlier_rounds},
          {"max_edge_rise_px", max_edge_rise_px},
          {"blur_median_factor", blur_median_factor},
          {"min_images", min_images},
          {"max_iterations", max_iterations},
          {"compute_covariance", compute_covariance},
          {"num_threads", num_threads}};
}

Json IntrinsicsStddev::ToJson() const {
  return {{"fx_px", fx_px}, {"fy_px", fy_px}, {"cx_px", cx_px}, {"cy_px", cy_px}, {"k1", k1},
          {"k2", k2},       {"p1", p1},       {"p2", p2},       {"k3", k3}};
}

Json RejectedImage::ToJson() const { return {{"file", file.string()}, {"reason", reason}}; }

Json ImageRms::ToJson() const {
  return {{"file", file.string()}, {"rms_px", rms_px}, {"max_error_px", max_error_px}};
}

Json IntrinsicsImage::ToJson() const {
  Json j = {{"file", file.string()}, {"used", used}};
  if (!used) j["reason"] = reason;
  if (!detector.empty()) j["detector"] = detector;
  if (edge_rise_px > 0) j["edge_rise_px"] = edge_rise_px;
  if (!residuals_px.empty()) {
    j["rms_px"] = rms_px;
    j["max_error_px"] = max_error_px;
    j["cam_from_board"] = {{"R", mesocap::ToJson(cam_from_board_R)}, {"t", mesocap::ToJson(cam_from_board_t)}};
  }
  if (!corners_px.empty()) {
    Json corners = Json::array();
    for (const auto& c : corners_px) corners.push_back({c.x(), c.y()});
    j["corners_px"] = std::move(corners);
  }
  return j;
}

Json IntrinsicsReport::ToJson() const {
  Json per = Json::array(), rej = Json::array();
  for (const auto& p : per_image) per.push_back(p.ToJson());
  for (const auto& r : rejected) rej.push_back(r.ToJson());
  return {{"images_total", images_total},
          {"images_used", images_used},
          {"images_rejected", images_rejected},
          {"corners_used", corners_used},
          {"rms_reprojection_px", rms_reprojection_px},
          {"initial_rms_px", initial_rms_px},
          {"median_image_rms_px", median_image_rms_px},
          {"max_image_rms_px", max_image_rms_px},
          {"median_edge_rise_px", median_edge_rise_px},
          {"stddev", covariance_ok ? stddev.ToJson() : Json(nullptr)},
          {"outlier_rounds", outlier_rounds},
          {"solver_iterations", solver_iterations},
          {"solver_summary", solver_summary},
          {"detect_s", detect_s},
          {"solve_s", solve_s},
          {"total_s", total_s},
          {"per_image", std::move(per)},
          {"rejected", std::move(rej)}};
}

std::string IntrinsicsReport::Brief() const {
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "calibrated from %d of %d images (%d corners): RMS %.3f px (OpenCV start %.3f px), image RMS "
                "median %.3f px max %.3f px, in %.1f s (detection %.1f s, solve %.1f s)",
                images_used, images_total, corners_used, rms_reprojection_px, initial_rms_px, median_image_rms_px,
                max_image_rms_px, total_s, detect_s, solve_s);
  // The JSON report lists them all.
  return buf + ListedLines(rejected, 20, "the JSON report", [](const RejectedImage& r) {
           return "rejected " + r.file.filename().string() + ": " + r.reason;
         });
}

Json IntrinsicsResult::ToJson() const {
  Json ims = Json::array();
  for (const auto& im : images) ims.push_back(im.ToJson());
  return {{"camera", camera.ToJson()}, {"report", report.ToJson()}, {"options", options.ToJson()},
          {"images", std::move(ims)}};
}

std::string IntrinsicsResult::Brief() const {
  const IntrinsicsStddev& s = report.stddev;
  std::string text = Format("%dx%d: ", camera.width, camera.height) +
                     Format("fx %.2f fy %.2f ", camera.K(0, 0), camera.K(1, 1)) +
                     Format("cx %.2f cy %.2f px", camera.K(0, 2), camera.K(1, 2));
  if (report.covariance_ok)
    text += Format(" (sd fx %.2f fy %.2f ", s.fx_px, s.fy_px) + Format("cx %.2f cy %.2f)", s.cx_px, s.cy_px);
  text += Format("; k1 %.5f k2 %.5f ", camera.dist[0], camera.dist[1]) +
          Format("p1 %.6f p2 %.6f k3 %.5f\n", camera.dist[2], camera.dist[3], camera.dist[4]);
  return text + report.Brief();
}

std::vector<Eigen::Vector3d> CheckerboardPoints(int cols, int rows, double square_m) {
  std::vector<Eigen::Vector3d> points;
  points.reserve(size_t(cols) * rows);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) points.emplace_back(c * square_m, r * square_m, 0.0);
  return points;
}

StatusOr<std::vector<std::filesystem::path>> ListCalibrationImages(const std::filesystem::path& dir) {
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) return Status::Error(dir.string() + ": not a folder");
  std::vector<std::filesystem::path> files;
  for (std::filesystem::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const auto& p = it->path();
    if (p.filename().string().starts_with(".") || !it->is_regular_file(ec)) continue;
    if (HasReadableImageExtension(p)) files.push_back(p);
  }
  if (ec) return Status::Error(dir.string() + ": cannot list the folder: " + ec.message());
  std::sort(files.begin(), files.end());
  return files;
}

StatusOr<IntrinsicsResult> CalibrateIntrinsics(const std::vector<std::filesystem::path>& files,
                                               const IntrinsicsOptions& options, const ProgressFn& progress) {
  MESOCAP_CHECK(options.Check().empty(), options.Check());
  const auto start = Clock::now();
  if (files.empty()) return Status::Error("no images given to calibrate from");
  const int n = int(files.size());

  IntrinsicsResult result;
  result.options = options;
  result.images.resize(n);
  for (int i = 0; i < n; ++i) result.images[i].file = files[i];

  // 1. Detection, in parallel; progress is reported under a lock, in completion order.
  std::vector<cv::Size> sizes(n, cv::Size(0, 0));
  std::atomic<bool> cancelled{false};
  std::mutex progress_mutex;
  int done = 0;
  ParallelFor(
      0, n,
      [&](int i) {
        if (cancelled) return;
        DetectCorners(options, &result.images[i], &sizes[i]);
        std::lock_guard<std::mutex> lock(progress_mutex);
        if (!ReportProgress(progress, ++done, n, "detect " + files[i].filename().string())) cancelled = true;
      },
      options.num_threads);
  if (cancelled) return Status::Cancelled();
  result.report.detect_s = SecondsSince(start);

  // 2. All images must share one size: the most common one among the readable images.
  std::map<std::pair<int, int>, int> size_count;
  for (const auto& s : sizes)
    if (s.width > 0) ++size_count[{s.width, s.height}];
  if (size_count.empty())
    return Status::Error("none of the " + std::to_string(n) + " images could be read (first: " +
                         files[0].string() + ": " + result.images[0].reason + ")");
  const auto common = std::max_element(size_count.begin(), size_count.end(),
                                       [](const auto& a, const auto& b) { return a.second < b.second; })
                          ->first;
  const cv::Size image_size(common.first, common.second);
  std::vector<int> active;
  for (int i = 0; i < n; ++i) {
    IntrinsicsImage& im = result.images[i];
    if (im.reason.empty() && sizes[i] != image_size) {
      im.reason = "image size " + std::to_string(sizes[i].width) + "x" + std::to_string(sizes[i].height) +
                  " differs from the other images' " + std::to_string(image_size.width) + "x" +
                  std::to_string(image_size.height);
    }
    if (im.reason.empty()) active.push_back(i);
  }
  // Blur: judged against the set, so a lens that is soft everywhere does not lose every image.
  std::vector<double> rises;
  for (const int i : active) rises.push_back(result.images[i].edge_rise_px);
  const double median_rise = Median(rises);
  const double rise_limit = std::max(options.max_edge_rise_px, options.blur_median_factor * median_rise);
  if (options.max_edge_rise_px > 0) {
    std::vector<int> sharp;
    for (const int i : active) {
      IntrinsicsImage& im = result.images[i];
      if (im.edge_rise_px > rise_limit) {
        im.reason = Format("blurred: board edges rise over %.2f px on average (limit %.2f px: the larger of "
                           "max_edge_rise_px and %.1f x the median)",
                           im.edge_rise_px, rise_limit, options.blur_median_factor);
      } else {
        sharp.push_back(i);
      }
    }
    active = std::move(sharp);
  }
  result.report.median_edge_rise_px = median_rise;
  auto list_reasons = [&]() {
    std::string text;
    for (int i = 0; i < n && i < 5; ++i)
      text += "\n  " + files[i].filename().string() + ": " + result.images[i].reason;
    if (n > 5) text += "\n  ...";
    return text;
  };
  if (active.empty()) {
    return Status::Error("no " + PatternName(options) + " checkerboard (inner corners) found in any of the " +
                         std::to_string(n) + " images; check --board:" + list_reasons());
  }
  if (int(active.size()) < options.min_images) {
    return Status::Error("a " + PatternName(options) + " checkerboard was found in only " +
                         std::to_string(active.size()) + " of " + std::to_string(n) + " images; at least " +
                         std::to_string(options.min_images) + " are needed:" + list_reasons());
  }

  // 3. Initial estimate: OpenCV on every usable image.
  const auto solve_start = Clock::now();
  const std::vector<Eigen::Vector3d> board = CheckerboardPoints(options.cols, options.rows, options.square_m);
  std::vector<std::vector<cv::Point3f>> object_points;
  std::vector<std::vector<cv::Point2f>> image_points;
  for (const int i : active) {
    std::vector<cv::Point3f> obj;
    std::vector<cv::Point2f> img;
    for (size_t j = 0; j < board.size(); ++j) {
      obj.emplace_back(float(board[j].x()), float(board[j].y()), 0.0f);
      img.emplace_back(float(result.images[i].corners_px[j].x()), float(result.images[i].corners_px[j].y()));
    }
    object_points.push_back(std::move(obj));
    image_points.push_back(std::move(img));
  }
  cv::Mat K, dist;
  std::vector<cv::Mat> rvecs, tvecs;
  try {
    result.report.initial_rms_px = cv::calibrateCamera(object_points, image_points, image_size, K, dist, rvecs, tvecs);
  } catch (const cv::Exception& e) {
    return Status::Error(std::string("cv::calibrateCamera failed on the detected corners: ") + e.what());
  }
  double intrinsics[kNumIntrinsics] = {K.at<double>(0, 0), K.at<double>(1, 1), K.at<double>(0, 2),
                                       K.at<double>(1, 2), 0, 0, 0, 0, 0};
  for (int k = 0; k < 5 && k < int(dist.total()); ++k) intrinsics[kK1 + k] = dist.at<double>(k);
  std::vector<std::array<double, kNumPoseParams>> poses(n);
  for (size_t a = 0; a < active.size(); ++a) {
    auto& pose = poses[active[a]];
    for (int k = 0; k < 3; ++k) {
      pose[k] = rvecs[a].at<double>(k);
      pose[3 + k] = tvecs[a].at<double>(k);
    }
  }

  // 4. Ceres refinement; images far above the median RMS are dropped and the solve repeated.
  SolveOutput solve;
  const int max_solves = options.max_outlier_rounds + 1;
  for (int round = 0;; ++round) {
    if (!ReportProgress(progress, round + 1, max_solves, "solve")) return Status::Cancelled();
    solve = SolveOnce(options, board, result.images, active, intrinsics, &poses, /*want_covariance=*/false);
    result.report.solver_iterations += solve.iterations;
    std::vector<double> rms;
    for (const int i : active) {
      EvaluateImage(board, intrinsics, poses[i].data(), &result.images[i]);
      rms.push_back(result.images[i].rms_px);
    }
    if (round >= options.max_outlier_rounds) break;
    const double median = Median(rms);
    const double limit = std::max(options.outlier_rms_factor * median, options.outlier_min_rms_px);
    std::vector<int> kept;
    for (const int i : active) {
      IntrinsicsImage& im = result.images[i];
      if (im.rms_px > limit) {
        im.reason = Format("outlier: reprojection RMS %.3f px is above %.3f px (%.1f x the median image RMS, "
                           "or the floor)",
                           im.rms_px, limit, options.outlier_rms_factor);
      } else {
        kept.push_back(i);
      }
    }
    if (kept.size() == active.size()) break;
    ++result.report.outlier_rounds;
    active = std::move(kept);
    if (int(active.size()) < options.min_images) {
      return Status::Error("only " + std::to_string(active.size()) + " images are left after rejecting outliers; at least " +
                           std::to_string(options.min_images) + " are needed");
    }
  }
  if (options.compute_covariance) {
    // A final solve from the converged estimate (no iterations to speak of) that also computes
    // the covariance on the same problem.
    solve = SolveOnce(options, board, result.images, active, intrinsics, &poses, /*want_covariance=*/true);
    result.report.solver_iterations += solve.iterations;
    for (const int i : active) EvaluateImage(board, intrinsics, poses[i].data(), &result.images[i]);
  }
  result.report.solver_summary = solve.summary;

  // 5. Results.
  CameraModel& cam = result.camera;
  cam.width = image_size.width;
  cam.height = image_size.height;
  cam.K << intrinsics[kFx], 0, intrinsics[kCx], 0, intrinsics[kFy], intrinsics[kCy], 0, 0, 1;
  for (int k = 0; k < 5; ++k) cam.dist[k] = intrinsics[kK1 + k];

  IntrinsicsReport& rep = result.report;
  rep.images_total = n;
  double sum2 = 0;
  std::vector<double> rms;
  for (const int i : active) {
    IntrinsicsImage& im = result.images[i];
    im.used = true;
    for (const auto& r : im.residuals_px) sum2 += r.squaredNorm();
    rep.corners_used += int(im.residuals_px.size());
    rms.push_back(im.rms_px);
    rep.max_image_rms_px = std::max(rep.max_image_rms_px, im.rms_px);
  }
  for (const auto& im : result.images) {
    if (im.used)
      rep.per_image.push_back({im.file, im.rms_px, im.max_error_px});
    else
      rep.rejected.push_back({im.file, im.reason});
  }
  rep.images_used = int(active.size());
  rep.images_rejected = n - rep.images_used;
  rep.rms_reprojection_px = std::sqrt(sum2 / std::max(1, rep.corners_used));
  rep.median_image_rms_px = Median(rms);
  if (solve.covariance_ok) {
    // Scale the unit-variance covariance by the residual variance per coordinate.
    const int dof = 2 * rep.corners_used - kNumIntrinsics - kNumPoseParams * rep.images_used;
    const double sigma2 = dof > 0 ? sum2 / dof : std::numeric_limits<double>::quiet_NaN();
    auto sd = [&](int k) { return std::sqrt(solve.covariance(k, k) * sigma2); };
    rep.stddev = {sd(kFx), sd(kFy), sd(kCx), sd(kCy), sd(kK1), sd(kK2), sd(kP1), sd(kP2), sd(kK3)};
    rep.covariance_ok = true;
  }
  rep.solve_s = SecondsSince(solve_start);
  rep.total_s = SecondsSince(start);
  return result;
}

}  // namespace mesocap
