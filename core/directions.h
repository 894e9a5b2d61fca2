// Directions on the hemisphere of a surface frame (z = normal): theta from the normal,
// phi = atan2(y, x). Angles in degrees at interfaces, radians inside formulas.
#pragma once

#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace mesocap {

inline double DegToRad(double deg) { return deg * std::numbers::pi / 180.0; }
inline double RadToDeg(double rad) { return rad * 180.0 / std::numbers::pi; }

inline Eigen::Vector3d DirectionFromAnglesDeg(double theta_deg, double phi_deg) {
  const double t = DegToRad(theta_deg), p = DegToRad(phi_deg);
  return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

// Returns {theta_deg, phi_deg}; phi in [0, 360).
inline Eigen::Vector2d AnglesDegFromDirection(const Eigen::Vector3d& d) {
  const Eigen::Vector3d n = d.normalized();
  const double theta = RadToDeg(std::acos(std::clamp(n.z(), -1.0, 1.0)));
  double phi = RadToDeg(std::atan2(n.y(), n.x()));
  if (phi < 0) phi += 360.0;
  return {theta, phi};
}

// Angle between two directions, in degrees, robust for nearly parallel vectors.
inline double AngleBetweenDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return RadToDeg(std::atan2(a.cross(b).norm(), a.dot(b)));
}

}  // namespace mesocap
