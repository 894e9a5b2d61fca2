// One pose per board from all its AprilTags over all shots (the boards never move): an initial
// planar PnP on the best shot, then a robust Ceres refinement of every tag corner seen.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "calib/tag_detection.h"
#include "core/camera_model.h"
#include "core/json.h"
#include "core/rig_layout.h"

namespace mesocap {

struct BoardPoseOptions {
  double huber_px = 1.0;        // robust loss scale for corner residuals
  int min_corners = 8;          // fewer (two tags' worth) and the board is not posed
};

struct BoardPose {
  int id = 0;
  bool found = false;
  std::string why_not;  // when !found: e.g. "tags never detected (hidden or unlit)"
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  // X_cam = R X_board + t
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  int corners_used = 0, shots_seen = 0;
  double rms_reprojection_px = 0;
  double rotation_stddev_deg = 0, translation_stddev_mm = 0;
  Json ToJson() const;
};

// detections[s] are the tags found in shot s. Serves the material boards and the grey cards'
// tagged mounts alike.
std::vector<BoardPose> EstimateBoardPoses(const CameraModel& camera, const std::vector<LayoutBoard>& boards,
                                          const std::vector<std::vector<TagDetection>>& detections,
                                          const BoardPoseOptions& options = {});

}  // namespace mesocap
