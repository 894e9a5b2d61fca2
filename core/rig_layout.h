// The physical description of a capture rig, as a lab knows it before any photo: board sizes
// and where each AprilTag sits on its board, the balls' radius, the grey cards' size and albedo,
// the checkerboard. Poses, lights and powers are what calibration finds; they are not here.
// Virtual sessions write it as rig_layout.json; a real lab writes its own (docs/formats.md).
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>

#include "core/json.h"
#include "core/status.h"

namespace mesocap {

struct LayoutTag {
  int id = 0;
  double size_m = 0;
  std::array<Eigen::Vector2d, 4> corners_m;  // board frame, libapriltag's corner order
};

struct LayoutBoard {
  int id = 0;
  double size_m = 0, patch_m = 0;
  double nominal_incidence_deg = 0;  // 0 (top), ~30 or ~60: groups views into rings
  std::vector<LayoutTag> tags;
};

struct RigLayout {
  std::vector<LayoutBoard> boards;
  std::string tag_family = "tag36h11";
  int sphere_count = 0;
  double sphere_radius_m = 0;
  // Grey cards on tagged mounts: size_m is the mount, patch_m the grey area.
  std::vector<LayoutBoard> grey_cards;
  double grey_card_albedo = 0;
  int checker_cols = 0, checker_rows = 0;
  double checker_square_m = 0;

  Json ToJson() const;
  static StatusOr<RigLayout> FromJson(const Json& j);
};

}  // namespace mesocap
