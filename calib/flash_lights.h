// Flash position per shot (Ngan & Durand section 2): the mirror highlight on each ball gives a
// reflected ray toward the flash; the rays from all balls meet at the flash (least squares).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "calib/spheres.h"
#include "core/camera_model.h"
#include "core/image.h"
#include "core/json.h"

namespace mesocap {

struct HighlightOptions {
  double min_whiteness = 0.25;     // min(R,G,B) at the peak, linear: below it, no highlight
  double blob_fraction = 0.85;     // pixels within this fraction of the peak form the highlight
  double max_blob_radius_px = 12;  // a larger bright area is not a mirror highlight
  int min_highlights = 2;          // fewer and the shot is flagged, not guessed
};

struct Highlight {
  int sphere = 0;
  bool found = false;
  std::string why_not;
  Eigen::Vector2d pixel{0, 0};
  Eigen::Vector3d origin_m = Eigen::Vector3d::Zero();     // point on the ball
  Eigen::Vector3d direction = Eigen::Vector3d::Zero();    // reflected ray, unit
};

struct LightEstimate {
  bool ok = false;
  std::string flag;  // why not ok
  Eigen::Vector3d light_m = Eigen::Vector3d::Zero();
  Eigen::Matrix3d covariance_m2 = Eigen::Matrix3d::Zero();
  int highlights_used = 0;
  double rms_ray_miss_mm = 0;  // distance of the solution from each ray
  std::vector<Highlight> highlights;
  Json ToJson() const;
};

// Finds each ball's highlight in one shot (linear image) and solves for the flash.
LightEstimate EstimateFlash(const CameraModel& camera, const std::vector<SphereEstimate>& spheres,
                            const Image& shot, const HighlightOptions& options = {});

}  // namespace mesocap
