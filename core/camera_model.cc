#include "core/camera_model.h"

#include <Eigen/Dense>

namespace mesocap {

Eigen::Vector2d CameraModel::Distort(const Eigen::Vector2d& xy) const {
  const double x = xy.x(), y = xy.y();
  const double r2 = x * x + y * y;
  const auto& [k1, k2, p1, p2, k3] = dist;
  const double radial = 1 + r2 * (k1 + r2 * (k2 + r2 * k3));
  return {x * radial + 2 * p1 * x * y + p2 * (r2 + 2 * x * x),
          y * radial + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y};
}

Eigen::Vector2d CameraModel::Undistort(const Eigen::Vector2d& target) const {
  // Newton's method with the analytic Jacobian of Distort; 3-4 steps reach 1e-12.
  const auto& [k1, k2, p1, p2, k3] = dist;
  Eigen::Vector2d xy = target;
  for (int it = 0; it < 20; ++it) {
    const double x = xy.x(), y = xy.y(), r2 = x * x + y * y;
    const double radial = 1 + r2 * (k1 + r2 * (k2 + r2 * k3));
    const double dradial = k1 + r2 * (2 * k2 + 3 * r2 * k3);  // d radial / d r2
    const Eigen::Vector2d residual(x * radial + 2 * p1 * x * y + p2 * (r2 + 2 * x * x) - target.x(),
                                   y * radial + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y - target.y());
    if (residual.squaredNorm() < 1e-26) break;
    Eigen::Matrix2d J;
    J(0, 0) = radial + 2 * x * x * dradial + 2 * p1 * y + 6 * p2 * x;
    J(0, 1) = 2 * x * y * dradial + 2 * p1 * x + 2 * p2 * y;
    J(1, 0) = 2 * x * y * dradial + 2 * p1 * x + 2 * p2 * y;
    J(1, 1) = radial + 2 * y * y * dradial + 6 * p1 * y + 2 * p2 * x;
    xy -= J.inverse() * residual;
  }
  return xy;
}

Eigen::Vector2d CameraModel::Project(const Eigen::Vector3d& p) const {
  const Eigen::Vector2d d = Distort(Eigen::Vector2d(p.x() / p.z(), p.y() / p.z()));
  return {K(0, 0) * d.x() + K(0, 1) * d.y() + K(0, 2), K(1, 1) * d.y() + K(1, 2)};
}

Eigen::Vector3d CameraModel::PixelToRay(const Eigen::Vector2d& px) const {
  const double yd = (px.y() - K(1, 2)) / K(1, 1);
  const double xd = (px.x() - K(0, 2) - K(0, 1) * yd) / K(0, 0);
  const Eigen::Vector2d xy = Undistort({xd, yd});
  return Eigen::Vector3d(xy.x(), xy.y(), 1.0).normalized();
}

Json CameraModel::ToJson() const {
  return {{"width", width}, {"height", height}, {"K", mesocap::ToJson(K)},
          {"dist", {dist[0], dist[1], dist[2], dist[3], dist[4]}}};
}

CameraModel CameraModel::FromJson(const Json& j) {
  CameraModel c;
  c.width = JsonInteger(JsonField(j, "", "width"), "width", 1, 1 << 17);
  c.height = JsonInteger(JsonField(j, "", "height"), "height", 1, 1 << 17);
  const Json& k = JsonArray(JsonField(j, "", "K"), "K", 3, 3);
  for (int r = 0; r < 3; ++r) {
    const std::string row = JsonIndexPath("K", r);
    JsonArray(k[r], row, 3, 3);
    for (int col = 0; col < 3; ++col) c.K(r, col) = JsonNumber(k[r][col], JsonIndexPath(row, col), -1e7, 1e7);
  }
  // A pinhole matrix: positive focal lengths, [0 0 1] last row; the principal point may lie
  // outside the image (cropped sensors) but not absurdly far.
  if (!(c.K(0, 0) > 0 && c.K(1, 1) > 0) || c.K(1, 0) != 0 || c.K(2, 0) != 0 || c.K(2, 1) != 0 || c.K(2, 2) != 1)
    throw JsonFieldError("K must be [[fx, s, cx], [0, fy, cy], [0, 0, 1]] with fx, fy > 0");
  const Json& dist = JsonArray(JsonField(j, "", "dist"), "dist", 5, 5);
  for (int i = 0; i < 5; ++i) c.dist[i] = JsonNumber(dist[i], JsonIndexPath("dist", i), -1e3, 1e3);
  return c;
}

}  // namespace mesocap
