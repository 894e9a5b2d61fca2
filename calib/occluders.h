// What might stand between a board's patch and the camera or the flash: the other boards, the
// balls and the grey cards' mounts, as calibration found them. Resampling skips the slices they
// shadow; capture guidance counts only the lights they leave (app/capture_guide.h).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "calib/calibrate.h"
#include "core/rig_layout.h"

namespace mesocap {

struct Occluders {
  struct Square {
    std::string name;
    Eigen::Matrix3d R;
    Eigen::Vector3d t;
    double half;
  };
  std::vector<Square> squares;
  std::vector<std::pair<Eigen::Vector3d, double>> spheres;  // centre, radius

  // The posed boards (layout sizes), the grey cards' mounts and the balls of a calibration.
  static Occluders Of(const CalibrationResult& calibration, const RigLayout& layout);

  // The first occluder the segment p -> q crosses (skipping `self`), or "".
  std::string Blocking(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const std::string& self) const;
};

std::string BoardName(int id);      // "board 7", as Occluders names boards
std::string GreyCardName(int k);   // "grey card 0": the k-th calibrated card's mount

// Fraction of the grid x grid points of a board's patch (side `patch_m`) from which the segment
// to `target` (camera frame) is blocked, and by what (the first blocker met).
double BlockedFraction(const Occluders& occluders, const BoardPose& pose, double patch_m, int grid,
                       const Eigen::Vector3d& target, std::string* by);

}  // namespace mesocap
