// OpenCV's pinhole + (k1, k2, p1, p2, k3) projection, templated for Ceres autodiff. The one
// definition every calibration cost functor uses; core/camera_model.cc is the double version.
#pragma once

namespace mesocap {

// intrinsics: fx, fy, cx, cy, k1, k2, p1, p2, k3. point: camera frame. Writes pixel (u, v).
template <typename T>
void ProjectWithDistortion(const T* intrinsics, const T* point, T* pixel) {
  const T x = point[0] / point[2], y = point[1] / point[2];
  const T r2 = x * x + y * y;
  const T& k1 = intrinsics[4];
  const T& k2 = intrinsics[5];
  const T& p1 = intrinsics[6];
  const T& p2 = intrinsics[7];
  const T& k3 = intrinsics[8];
  const T radial = T(1) + r2 * (k1 + r2 * (k2 + r2 * k3));
  const T xd = x * radial + T(2) * p1 * x * y + p2 * (r2 + T(2) * x * x);
  const T yd = y * radial + p1 * (r2 + T(2) * y * y) + T(2) * p2 * x * y;
  pixel[0] = intrinsics[0] * xd + intrinsics[2];
  pixel[1] = intrinsics[1] * yd + intrinsics[3];
}

}  // namespace mesocap
