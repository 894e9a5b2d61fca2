// Checks of a flash shot beyond its flash position, for the operator while the session is shot
// (`capture --guide`, the console): boards whose patch is overexposed (resampling skips their
// slice: its rule and thresholds, calib/resample.h), no grey card to read the flash's power from
// (calibration then uses the session's mean power), and blur (camera shake or lost focus): the
// top board's edges less sharp than the session's own shots. Each is a warning in words; the
// shot stays in the session.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "calib/calibrate.h"
#include "core/image.h"
#include "core/rig_layout.h"

namespace mesocap::app {

struct ShotCheckOptions {
  double saturation_level = 0.99;       // linear, any channel: as resampling counts saturated texels
  double max_saturated_fraction = 0.01; // of a patch's texels: above it resampling skips the slice
  // Blurred: the top board's edge sharpness below this fraction of the median of the session's
  // shots so far (from the third on). A blur of about 2 px (a small shake) brings it to 30% on the
  // virtual rig, while its unblurred shots stay above the threshold (app/capture_guide_test).
  double min_sharpness_ratio = 0.6;
  int sharpness_baseline_shots = 3;
};

// The sharpness of the top board's edges in `shot`: the mean of its strongest tenth of gradients
// over the board's contrast (2nd to 98th percentile), on the board resampled to 256 texels.
// Independent of the flash's brightness; falls with blur. 0 when the board is not in view.
double TopBoardSharpness(const Image& shot, const CalibrationResult& rig, const RigLayout& layout);

// Warnings for `shot` (linear RGB) taken with the flash at `flash` (camera frame, when the balls
// gave it); `earlier_sharpness`: TopBoardSharpness of the session's shots so far.
std::vector<std::string> CheckShot(const Image& shot, const CalibrationResult& rig, const RigLayout& layout,
                                   const std::optional<Eigen::Vector3d>& flash, const std::vector<double>& earlier_sharpness,
                                   double sharpness, const ShotCheckOptions& options = {});

}  // namespace mesocap::app
