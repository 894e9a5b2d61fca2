// The virtual rig of ../shared/design.md: a fixed camera about 1 m above a pyramid of 13
// material boards with AprilTags, billiard balls that mirror the flash, grey cards that measure
// its power, a flash moved by hand, and a checkerboard for calibration. Everything the rig
// knows is ground truth, stored in truth.json in the camera frame (OpenCV: x right, y down,
// z forward), metres.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/camera_model.h"
#include "core/json.h"
#include "core/rig_layout.h"
#include "core/status.h"

namespace mesocap {

struct RigOptions {
  std::string material = "weave";
  int shots = 100;          // flash shots
  int calib_shots = 15;     // checkerboard poses
  uint64_t seed = 1;
  int width = 3000, height = 2000;

  // Empty when valid, otherwise the reason (a bad user option).
  std::string Check() const;
  Json ToJson() const;
};

struct RigTag {
  int id = 0;
  double size_m = 0;  // side of the black border square (libapriltag's tag size)
  // Corners in the board frame, in libapriltag's order: p[0..3] = bottom-left, bottom-right,
  // top-right, top-left of the upright tag (counter-clockwise as seen in the image).
  std::array<Eigen::Vector2d, 4> corners_m;
  Eigen::Vector2d centre_m{0, 0};
};

struct RigBoard {
  int id = 0;
  double tilt_deg = 0;            // board normal against the table's normal
  double view_incidence_deg = 0;  // board normal against the direction to the camera
  double size_m = 0.12;           // square backing board side
  double patch_m = 0.064;         // square material patch side, centred, clear of the tags
  Eigen::Vector2d material_offset_m{0, 0};  // where this board's patch sits in the material
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  // X_cam = R * X_board + t; z = board normal
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  std::vector<RigTag> tags;
};

struct RigSphere {
  Eigen::Vector3d center_m = Eigen::Vector3d::Zero();
  double radius_m = 0.028575;            // a 57.15 mm billiard ball
  Eigen::Vector3d base_rgb{0.5, 0.5, 0.5};  // diffuse base under the clear coat
  double coat_f0 = 0.05, coat_roughness = 0.02;
};

// A grey card glued on a white mount with AprilTags in its corners, like a material board, so
// calibration poses it with the same code (a bare grey square's tilt is ambiguous from its outline).
struct RigGreyCard {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  // X_cam = R * X_card + t; z = card normal
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  double size_m = 0.10;   // the mount
  double patch_m = 0.052;  // the grey card, centred on the mount
  double albedo = 0.18;
  std::vector<RigTag> tags;
};

struct RigShot {
  std::string file;  // relative to the session root
  Eigen::Vector3d light_m = Eigen::Vector3d::Zero();  // flash position, camera frame
  double power = 1.0;  // irradiance at 1 m on a surface facing the flash
};

struct RigCalibShot {
  std::string file;
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  // X_cam = R * X_checker + t
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
};

struct RigCheckerboard {
  int cols = 9, rows = 6;  // inner corners (OpenCV's patternSize)
  double square_m = 0.035;
  double margin_m = 0.025;  // white border beyond the outer squares
};

struct RigScene {
  RigOptions options;
  CameraModel camera;
  Eigen::Matrix3d cam_from_world_R = Eigen::Matrix3d::Identity();  // world: table, z up
  Eigen::Vector3d cam_from_world_t = Eigen::Vector3d::Zero();
  std::vector<RigBoard> boards;
  std::vector<RigSphere> spheres;
  std::vector<RigGreyCard> grey_cards;
  double table_albedo = 0.08;
  double board_albedo = 0.85, tag_black_albedo = 0.03;
  RigCheckerboard checkerboard;
  std::vector<RigShot> shots;
  std::vector<RigCalibShot> calib_shots;
  double exposure = 0.55;  // pixel value per unit radiance: a white board 0.5 m from the flash stays below clipping
  double ambient_radiance_calib = 0.8;  // room light on the checkerboard, times albedo
  double noise_shot = 1e-4, noise_read = 4e-6;  // variance = shot * v + read

  Eigen::Vector3d TableNormalInCam() const { return cam_from_world_R.col(2); }
  Eigen::Vector3d TablePointInCam() const { return cam_from_world_t; }
};

// Lays out the rig for `options` (deterministic in options.seed).
StatusOr<RigScene> MakeRigScene(const RigOptions& options);

Json TruthToJson(const RigScene& scene);
// What a lab would know of this rig before calibrating: sizes and tag layouts, no poses.
RigLayout LayoutOf(const RigScene& scene);
StatusOr<RigScene> TruthFromJson(const Json& truth);

}  // namespace mesocap
