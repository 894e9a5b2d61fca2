// The Ceres cost functor of the checkerboard intrinsics refinement: one board corner reprojected
// through cam_from_board (angle-axis, translation) and K with OpenCV's 5-coefficient distortion.
// Same model as CameraModel::Project (core/camera_model.h), zero skew.
#pragma once

#include <ceres/autodiff_cost_function.h>
#include <ceres/rotation.h>

#include <Eigen/Core>

#include "calib/projection.h"

namespace mesocap {

// Layout of the shared intrinsics parameter block (ProjectWithDistortion's).
enum IntrinsicsParam { kFx = 0, kFy, kCx, kCy, kK1, kK2, kP1, kP2, kK3, kNumIntrinsics };
// Per-image pose block: angle-axis rotation (3) then translation (3), X_cam = R X_board + t.
inline constexpr int kNumPoseParams = 6;

struct CheckerboardReprojectionCost {
  CheckerboardReprojectionCost(const Eigen::Vector2d& observed_px, const Eigen::Vector3d& point_in_board)
      : observed_px(observed_px), point_in_board(point_in_board) {}

  // residuals = projected - observed, in pixels.
  template <typename T>
  bool operator()(const T* intrinsics, const T* cam_from_board, T* residuals) const {
    const T point[3] = {T(point_in_board.x()), T(point_in_board.y()), T(point_in_board.z())};
    T point_in_cam[3];
    ceres::AngleAxisRotatePoint(cam_from_board, point, point_in_cam);
    for (int i = 0; i < 3; ++i) point_in_cam[i] += cam_from_board[3 + i];
    T pixel[2];
    ProjectWithDistortion(intrinsics, point_in_cam, pixel);
    residuals[0] = pixel[0] - T(observed_px.x());
    residuals[1] = pixel[1] - T(observed_px.y());
    return true;
  }

  static ceres::CostFunction* Create(const Eigen::Vector2d& observed_px, const Eigen::Vector3d& point_in_board) {
    return new ceres::AutoDiffCostFunction<CheckerboardReprojectionCost, 2, kNumIntrinsics, kNumPoseParams>(
        new CheckerboardReprojectionCost(observed_px, point_in_board));
  }

  Eigen::Vector2d observed_px;
  Eigen::Vector3d point_in_board;
};

}  // namespace mesocap
