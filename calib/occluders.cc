#include "calib/occluders.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

namespace mesocap {

namespace {

// Segment p + s (q - p), s in (0, 1), against the square |x|,|y| <= half of the frame (R, t).
bool SegmentHitsSquare(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Matrix3d& R,
                       const Eigen::Vector3d& t, double half) {
  const Eigen::Vector3d pl = R.transpose() * (p - t), ql = R.transpose() * (q - t);
  if ((pl.z() > 0) == (ql.z() > 0)) return false;
  const double s = pl.z() / (pl.z() - ql.z());
  const Eigen::Vector3d h = pl + s * (ql - pl);
  return s > 1e-9 && s < 1 - 1e-9 && std::abs(h.x()) <= half && std::abs(h.y()) <= half;
}

bool SegmentHitsSphere(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Vector3d& c, double r) {
  const Eigen::Vector3d d = q - p;
  const double s = std::clamp((c - p).dot(d) / d.squaredNorm(), 0.0, 1.0);
  return (p + s * d - c).squaredNorm() < r * r;
}

}  // namespace

std::string BoardName(int id) { return "board " + std::to_string(id); }
std::string GreyCardName(int k) { return "grey card " + std::to_string(k); }

Occluders Occluders::Of(const CalibrationResult& calibration, const RigLayout& layout) {
  Occluders occ;
  for (const BoardPose& pose : calibration.boards) {
    if (!pose.found) continue;
    double size_m = 0;
    for (const auto& lb : layout.boards)
      if (lb.id == pose.id) size_m = lb.size_m;
    occ.squares.push_back({BoardName(pose.id), pose.R, pose.t, size_m / 2});
  }
  double mount_m = 0;
  for (const auto& c : layout.grey_cards) mount_m = std::max(mount_m, c.size_m);
  for (size_t k = 0; k < calibration.grey_cards.size(); ++k) {
    const GreyCard& c = calibration.grey_cards[k];
    occ.squares.push_back({GreyCardName(int(k)), c.R, c.t, std::max(mount_m, c.size_m) / 2});
  }
  for (const auto& s : calibration.spheres.spheres) occ.spheres.push_back({s.center_m, s.radius_m});
  return occ;
}

std::string Occluders::Blocking(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const std::string& self) const {
  for (const auto& s : squares)
    if (s.name != self && SegmentHitsSquare(p, q, s.R, s.t, s.half)) return s.name;
  for (size_t k = 0; k < spheres.size(); ++k)
    if (SegmentHitsSphere(p, q, spheres[k].first, spheres[k].second)) return "ball " + std::to_string(k);
  return "";
}

double BlockedFraction(const Occluders& occ, const BoardPose& pose, double patch_m, int grid,
                       const Eigen::Vector3d& target, std::string* by) {
  int blocked = 0;
  for (int j = 0; j < grid; ++j)
    for (int i = 0; i < grid; ++i) {
      const double x = patch_m * ((i + 0.5) / grid - 0.5), y = patch_m * ((j + 0.5) / grid - 0.5);
      const Eigen::Vector3d p = pose.R * Eigen::Vector3d(x, y, 0) + pose.t;
      const std::string b = occ.Blocking(p, target, BoardName(pose.id));
      if (!b.empty()) {
        if (by->empty()) *by = b;
        ++blocked;
      }
    }
  return double(blocked) / (grid * grid);
}

}  // namespace mesocap
