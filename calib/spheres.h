// Billiard balls in 3D from their silhouettes and the known radius: the balls are found as round
// bright blobs in the per-pixel maximum over all shots, their outline is refined to sub-pixel
// along radial profiles, and each outline ray is tangent to the sphere (Ceres least squares).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/camera_model.h"
#include "core/image.h"
#include "core/json.h"

namespace mesocap {

struct SphereOptions {
  double radius_m = 0.028575;
  int expected_count = 4;
  double min_circularity = 0.85;  // blob area over its enclosing circle's area
};

struct SphereEstimate {
  Eigen::Vector3d center_m = Eigen::Vector3d::Zero();
  double radius_m = 0;
  Eigen::Vector2d image_centre_px{0, 0};
  double image_radius_px = 0;
  int outline_points = 0;
  double rms_tangent_error_mm = 0;  // outline rays' distance to the sphere surface
  Json ToJson() const;
};

struct SphereReport {
  std::vector<SphereEstimate> spheres;     // sorted by image x then y
  std::vector<std::string> rejected_blobs;  // why round-ish bright blobs were not taken
};

// `max_image`: linear, the per-pixel maximum over the flash shots (every side of a ball is lit
// by some shot): finds the balls. `mean_image`: the per-pixel mean, where the outline is
// measured: a pixel half ball, half table is the mean of the two there, but never reaches the
// mean of their maxima (they peak in different shots), so the maximum pulls outlines inward.
SphereReport LocateSpheres(const CameraModel& camera, const Image& max_image, const Image& mean_image,
                           const SphereOptions& options);

}  // namespace mesocap
