// `mesocap calibrate SESSION`: board poses, balls, flash position and power per shot, written
// to SESSION/calibration/rig.json with truth.json's keys for everything estimated, plus a
// report of every rejected item and why. Never reads truth.json.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "calib/board_poses.h"
#include "calib/flash_lights.h"
#include "calib/flash_power.h"
#include "calib/spheres.h"
#include "calib/tag_detection.h"
#include "core/camera_model.h"
#include "core/json.h"
#include "core/progress.h"
#include "core/rig_layout.h"
#include "core/status.h"

namespace mesocap {

struct CalibrateOptions {
  std::filesystem::path session;
  int pose_shots = 16;  // shots searched for tags (the boards never move; spread over the session)
  // Hand-marked board corners (calib/marked_corners.h), for boards whose tags are never decoded.
  std::filesystem::path marked_corners;
  int num_threads = -1;
  TagDetectOptions tags;
  BoardPoseOptions poses;
  HighlightOptions highlights;
  std::string Check() const;
};

struct ShotCalibration {
  std::string file;
  LightEstimate light;
  std::vector<CardReading> cards;
  double power_x_exposure = 0;
  double power = 0;  // relative: mean over the session's usable shots = 1
  std::string flag;  // why the shot is not fully usable
};

struct CalibrationResult {
  CameraModel camera;
  std::vector<BoardPose> boards;
  SphereReport spheres;
  std::vector<GreyCard> grey_cards;
  std::vector<ShotCalibration> shots;
  std::vector<std::string> rejected;  // every rejected item, with the reason
  double seconds_total = 0;
  int usable_shots() const;
  Json RigJson() const;     // truth.json's keys
  // What RigJson wrote, back (calibration/rig.json): all that resampling and the report need.
  // Reports that RigJson leaves out (per-card readings, highlights, rejected items) stay empty.
  // Throws JsonFieldError naming the field.
  static CalibrationResult FromRigJson(const Json& rig);
  Json ReportJson() const;  // calibration/report.json
  // ReportJson's `rejected`, back; throws JsonFieldError naming the field.
  static std::vector<std::string> RejectedFromReportJson(const Json& report);
  std::string Brief() const;
};

// How the balls are found on this rig: its layout's ball radius and count.
SphereOptions SphereOptionsFor(const RigLayout& layout);

// Runs every calibration step on a session whose intrinsics are `camera`.
StatusOr<CalibrationResult> CalibrateSession(const CalibrateOptions& options, const RigLayout& layout,
                                             const CameraModel& camera, const ProgressFn& progress = nullptr);

}  // namespace mesocap
