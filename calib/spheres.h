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
  int expected_count = 4;          // more ball-like blobs: the most completely outlined are kept
  double min_ball_to_background = 2.5;  // a ball's blob in the maximum image: this much brighter than around it
  double min_circularity = 0.6;    // blob area (convex hull) over its enclosing circle's area; the
                                   // outline, measured all round, decides whether it is a ball
  int n_rays = 360;                // radial profiles where the outline is measured
  double min_outline_fraction = 0.3;  // of the profiles, with a clear ball-to-background step
  // Locate the outline's halfway point in gamma-encoded values: right for JPEG shots, whose
  // chroma subsampling blurs edges after encoding (measured in linear values their outlines
  // come out 0.1-0.45 px small). For linear files (16-bit, float) false is exact; true moves a
  // 1 px anti-aliasing ramp's halfway point outward by up to ~0.1 px (computed for a 5:1 step).
  bool outline_encoded = true;
  std::string Check() const;       // empty when valid
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
// by some shot): finds the balls. `mean_image` (or a sum): the per-pixel mean, where the outline
// is measured: a pixel half ball, half table is the mean of the two there, but never reaches the
// mean of their maxima (they peak in different shots), so the maximum pulls outlines inward.
// The outline point on each radial profile is where the profile is halfway between the ball's
// and the background's levels, each fitted locally beside the edge (the edge of a box-filtered
// step); the undistorted rays through the outline are tangent to the ball (the perspective
// silhouette is an ellipse, never fitted as a circle), which gives its centre.
SphereReport LocateSpheres(const CameraModel& camera, const Image& max_image, const Image& mean_image,
                           const SphereOptions& options);

}  // namespace mesocap
