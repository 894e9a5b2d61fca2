// Camera intrinsics from photographs of a flat checkerboard (issue 4, step 1, and
// `mesocap calibrate-camera`): detect the inner corners in every image, initialise with
// cv::calibrateCamera, refine with Ceres (robust loss, shared intrinsics, one pose per image),
// reject outlier images and list every image that was not used with the reason.
//
// Model: core/camera_model.h, a pinhole with OpenCV's 5 distortion coefficients (k1, k2, p1, p2,
// k3), zero skew. Pixel (0, 0) is the centre of the top-left pixel, as in OpenCV.
// Board frame: origin at the first inner corner, x along cols, y along rows, z = 0 on the board
// (docs/formats.md, `checkerboard`); cam_from_board maps board points into the camera frame.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/camera_model.h"
#include "core/json.h"
#include "core/progress.h"
#include "core/status.h"

namespace mesocap {

enum class RobustLoss { kNone, kHuber, kCauchy };
std::string RobustLossToString(RobustLoss loss);                  // "none", "huber", "cauchy"
bool StringToRobustLoss(const std::string& s, RobustLoss* loss);  // false when unknown

// How the corners are located to sub-pixel precision. Both fall back to the classic
// cv::findChessboardCorners + cv::cornerSubPix when findChessboardCornersSB finds nothing.
// On the virtual rig (1500x1000 JPEGs) kSubPix was both faster (~0.3 s against ~2 s an image on
// one core; against ~14 s at 3000x2000) and closer to the true corners (0.09 px RMS against
// 0.125 px).
enum class CornerRefinement {
  kSubPix,      // findChessboardCornersSB on a copy scaled to max_detect_side_px, then
                // cv::cornerSubPix on the full image
  kSbAccuracy,  // cv::findChessboardCornersSB with CALIB_CB_ACCURACY on the full image
};
std::string CornerRefinementToString(CornerRefinement r);                  // "subpix", "sb-accuracy"
bool StringToCornerRefinement(const std::string& s, CornerRefinement* r);  // false when unknown

struct IntrinsicsOptions {
  int cols = 9, rows = 6;   // inner corners (OpenCV patternSize): cols along x, rows along y
  double square_m = 0.035;  // side of one square

  CornerRefinement refinement = CornerRefinement::kSubPix;
  int max_detect_side_px = 1600;  // kSubPix: the board is found on a copy at most this large

  RobustLoss loss = RobustLoss::kHuber;
  double loss_scale_px = 1.0;  // residuals (px) beyond this are down-weighted by the robust loss

  // An image whose RMS reprojection error exceeds outlier_rms_factor x the median image RMS
  // and also outlier_min_rms_px is rejected as an outlier and the solve is repeated without it.
  double outlier_rms_factor = 3.0;
  double outlier_min_rms_px = 0.5;
  int max_outlier_rounds = 3;

  // A detected board whose edges rise (10% -> 90%, cv::estimateChessboardSharpness) over more
  // than this many pixels on average, and over more than blur_median_factor x the median of the
  // images, is rejected as blurred. max_edge_rise_px <= 0 disables the test.
  double max_edge_rise_px = 4.0;
  double blur_median_factor = 2.0;

  int min_images = 3;           // fewer usable images than this is an error
  int max_iterations = 100;     // Ceres iterations per solve
  bool compute_covariance = true;  // parameter standard deviations (ceres::Covariance)
  int num_threads = -1;         // detection threads, -1: all cores (the solve is single-threaded)

  std::string Check() const;  // empty when valid, else a message for the user
  Json ToJson() const;
};

// Standard deviations of the intrinsics (1 sigma), from the Ceres covariance scaled by the
// residual variance. Only meaningful when IntrinsicsReport::covariance_ok (else zero, and null
// in the JSON): not computed, or the problem was rank-deficient.
struct IntrinsicsStddev {
  double fx_px = 0, fy_px = 0, cx_px = 0, cy_px = 0;
  double k1 = 0, k2 = 0, p1 = 0, p2 = 0, k3 = 0;
  Json ToJson() const;
};

// One input image, used or not.
struct IntrinsicsImage {
  std::filesystem::path file;
  bool used = false;
  std::string reason;             // why not used (empty when used)
  std::string detector;           // "sb-accuracy", "sb+subpix" or "classic+subpix"
  double edge_rise_px = 0;        // mean edge rise distance; larger = blurrier (0: not measured)
  double rms_px = 0;              // RMS reprojection error over this image's corners (0 when not solved)
  double max_error_px = 0;        // largest corner reprojection error
  std::vector<Eigen::Vector2d> corners_px;    // detected corners, row-major (solver input)
  std::vector<Eigen::Vector2d> residuals_px;  // projected - detected, per corner (when solved)
  Eigen::Matrix3d cam_from_board_R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d cam_from_board_t = Eigen::Vector3d::Zero();
  Json ToJson() const;
};

struct RejectedImage {
  std::filesystem::path file;
  std::string reason;  // "no 9x6 checkerboard found", "blurred: ...", "outlier: ...", a read error
  Json ToJson() const;
};

struct ImageRms {
  std::filesystem::path file;
  double rms_px = 0, max_error_px = 0;
  Json ToJson() const;
};

struct IntrinsicsReport {
  int images_total = 0, images_used = 0, images_rejected = 0;
  int corners_used = 0;
  std::vector<ImageRms> per_image;      // used images, in input order
  std::vector<RejectedImage> rejected;  // in input order
  double rms_reprojection_px = 0;     // over all corners of the used images, after refinement
  double initial_rms_px = 0;          // cv::calibrateCamera's RMS on the same images
  double median_image_rms_px = 0, max_image_rms_px = 0;
  double median_edge_rise_px = 0;     // sharpness of the detected boards (smaller = sharper)
  IntrinsicsStddev stddev;
  bool covariance_ok = false;
  int outlier_rounds = 0;
  int solver_iterations = 0;
  std::string solver_summary;         // Ceres BriefReport of the last solve
  double detect_s = 0, solve_s = 0, total_s = 0;

  Json ToJson() const;  // without per-image corners (see IntrinsicsResult::ToJson)
  std::string Brief() const;
};

struct IntrinsicsResult {
  CameraModel camera;
  IntrinsicsReport report;
  std::vector<IntrinsicsImage> images;  // in input order
  IntrinsicsOptions options;            // as used

  // {"camera": CameraModel::ToJson, "report": ..., "options": ..., "images": [...]}; the images
  // carry their detected corners and poses so the solve (and its uncertainty) can be redone.
  Json ToJson() const;
  std::string Brief() const;  // the intrinsics with their standard deviations, then report.Brief()
};

// Calibrates from `images` (the caller lists the folder). Every image that cannot be read, has
// another size than the first readable one, shows no checkerboard, is blurred or is an outlier
// is listed in the result with the reason; the rest are used.
// Errors: invalid options; no usable image ("no 9x6 checkerboard found in any of N images ...");
// fewer than min_images usable; "cancelled" when `progress` returns false.
// Progress: one step per image detected, then one per solve.
StatusOr<IntrinsicsResult> CalibrateIntrinsics(const std::vector<std::filesystem::path>& images,
                                               const IntrinsicsOptions& options,
                                               const ProgressFn& progress = nullptr);

// The board's inner corners in the board frame, row-major (cols along x, rows along y).
std::vector<Eigen::Vector3d> CheckerboardPoints(int cols, int rows, double square_m);

// Lists the image files of a folder (by extension: jpg, jpeg, png, tif, tiff, exr and common
// camera RAW), sorted by name, not recursive. Error when the folder cannot be listed.
StatusOr<std::vector<std::filesystem::path>> ListCalibrationImages(const std::filesystem::path& dir);

}  // namespace mesocap
