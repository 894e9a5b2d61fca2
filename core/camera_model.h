// Pinhole camera with OpenCV's 5-parameter distortion (k1, k2, p1, p2, k3).
// Frame: OpenCV convention, x right, y down, z forward; pixel (0,0) is the centre of the
// top-left pixel, as in OpenCV, so projections compare directly with cv::calibrateCamera.
#pragma once

#include <array>

#include <Eigen/Core>

#include "core/json.h"

namespace mesocap {

struct CameraModel {
  int width = 0, height = 0;
  Eigen::Matrix3d K = Eigen::Matrix3d::Identity();
  std::array<double, 5> dist{0, 0, 0, 0, 0};  // k1, k2, p1, p2, k3

  // Normalised image coordinates (x/z, y/z) -> distorted normalised coordinates.
  Eigen::Vector2d Distort(const Eigen::Vector2d& xy) const;
  // Inverse of Distort, by Newton iteration (to 1e-12 in normalised units).
  Eigen::Vector2d Undistort(const Eigen::Vector2d& xy_distorted) const;
  // Camera-frame point -> pixel.
  Eigen::Vector2d Project(const Eigen::Vector3d& point_in_cam) const;
  // Pixel -> unit ray direction in the camera frame.
  Eigen::Vector3d PixelToRay(const Eigen::Vector2d& pixel) const;

  Json ToJson() const;
  // Throws JsonFieldError (naming the field) on a missing, mistyped or out-of-range field.
  static CameraModel FromJson(const Json& j);
};

}  // namespace mesocap
