#include "app/rig_plot.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <opencv2/imgproc.hpp>

#include "core/text_format.h"

namespace mesocap::app {
namespace {

// Points in the top board's frame, by kind.
struct RigPoints {
  std::vector<std::vector<Eigen::Vector3d>> patches;  // each board's patch corners
  std::vector<Eigen::Vector3d> balls, flashes;
  Eigen::Vector3d camera = Eigen::Vector3d::Zero();
};

RigPoints InTopFrame(const CalibrationResult& result, const RigLayout& layout, const BoardPose& top) {
  auto to_top = [&](const Eigen::Vector3d& camera_point) -> Eigen::Vector3d {
    return top.R.transpose() * (camera_point - top.t);
  };
  RigPoints points;
  for (const BoardPose& b : result.boards) {
    if (!b.found) continue;
    double half = 0.03;
    for (const LayoutBoard& lb : layout.boards)
      if (lb.id == b.id) half = lb.patch_m / 2;
    std::vector<Eigen::Vector3d> corners;
    for (const auto& [u, v] : {std::pair{-1, -1}, {1, -1}, {1, 1}, {-1, 1}})
      corners.push_back(to_top(b.R * Eigen::Vector3d(u * half, v * half, 0) + b.t));
    points.patches.push_back(corners);
  }
  for (const SphereEstimate& s : result.spheres.spheres) points.balls.push_back(to_top(s.center_m));
  for (const ShotCalibration& shot : result.shots)
    if (shot.light.ok) points.flashes.push_back(to_top(shot.light.light_m));
  points.camera = to_top(Eigen::Vector3d::Zero());
  return points;
}

// One orthographic panel: world (a, b) -> pixels, b up, one scale for both axes.
struct Panel {
  cv::Mat canvas;
  cv::Point origin;  // pixel of the panel's top-left
  double min_a = 0, min_b = 0, scale = 1;
  int size = 0;
  cv::Point At(double a, double b) const {
    return origin + cv::Point(int(std::lround(30 + (a - min_a) * scale)), int(std::lround(size - 20 - (b - min_b) * scale)));
  }
};

Panel MakePanel(cv::Mat canvas, cv::Point origin, int size, const std::vector<Eigen::Vector2d>& extent) {
  Panel p{canvas, origin};
  p.size = size;
  double max_a = -1e9, max_b = -1e9;
  p.min_a = p.min_b = 1e9;
  for (const Eigen::Vector2d& q : extent) {
    p.min_a = std::min(p.min_a, q.x()), max_a = std::max(max_a, q.x());
    p.min_b = std::min(p.min_b, q.y()), max_b = std::max(max_b, q.y());
  }
  const double span = std::max({max_a - p.min_a, max_b - p.min_b, 1e-3});
  p.scale = (size - 60) / span;
  // Centre the shorter axis.
  p.min_a -= (span - (max_a - p.min_a)) / 2;
  p.min_b -= (span - (max_b - p.min_b)) / 2;
  return p;
}

void DrawPanel(const Panel& p, const RigPoints& points, const std::function<Eigen::Vector2d(const Eigen::Vector3d&)>& project,
               const std::string& title, const std::string& axes) {
  const cv::Scalar patch(0.55, 0.55, 0.6), ball(0.9, 0.9, 0.9), flash(1.0, 0.75, 0.2), camera(0.3, 0.8, 1.0);
  for (const auto& corners : points.patches)
    for (size_t k = 0; k < corners.size(); ++k) {
      const Eigen::Vector2d a = project(corners[k]), b = project(corners[(k + 1) % corners.size()]);
      cv::line(p.canvas, p.At(a.x(), a.y()), p.At(b.x(), b.y()), patch, 1, cv::LINE_AA);
    }
  for (const Eigen::Vector3d& b : points.balls) {
    const Eigen::Vector2d q = project(b);
    cv::circle(p.canvas, p.At(q.x(), q.y()), 4, ball, 1, cv::LINE_AA);
  }
  for (const Eigen::Vector3d& f : points.flashes) {
    const Eigen::Vector2d q = project(f);
    cv::circle(p.canvas, p.At(q.x(), q.y()), 3, flash, cv::FILLED, cv::LINE_AA);
  }
  const Eigen::Vector2d c = project(points.camera);
  const cv::Point cp = p.At(c.x(), c.y());
  cv::drawMarker(p.canvas, cp, camera, cv::MARKER_TRIANGLE_UP, 12, 2, cv::LINE_AA);
  cv::putText(p.canvas, "camera", cp + cv::Point(8, -6), cv::FONT_HERSHEY_SIMPLEX, 0.35, camera, 1, cv::LINE_AA);
  cv::putText(p.canvas, title, p.origin + cv::Point(10, 18), cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(0.9, 0.9, 0.9), 1,
              cv::LINE_AA);
  cv::putText(p.canvas, axes, p.origin + cv::Point(10, p.size - 4), cv::FONT_HERSHEY_SIMPLEX, 0.35,
              cv::Scalar(0.6, 0.6, 0.6), 1, cv::LINE_AA);
  // A 10 cm scale bar.
  const cv::Point bar = p.origin + cv::Point(p.size - 30 - int(0.1 * p.scale), 30);
  cv::line(p.canvas, bar, bar + cv::Point(int(0.1 * p.scale), 0), cv::Scalar(0.8, 0.8, 0.8), 2);
  cv::putText(p.canvas, "10 cm", bar + cv::Point(0, -5), cv::FONT_HERSHEY_SIMPLEX, 0.35, cv::Scalar(0.8, 0.8, 0.8), 1,
              cv::LINE_AA);
}

}  // namespace

const BoardPose* TopBoardPose(const CalibrationResult& result) {
  const BoardPose* top = nullptr;
  for (const BoardPose& b : result.boards)
    if (b.found && (!top || std::abs(b.R(2, 2)) > std::abs(top->R(2, 2)))) top = &b;
  return top;
}

Image FlashPositionsPlot(const CalibrationResult& result, const RigLayout& layout, int panel_size) {
  const BoardPose* top = TopBoardPose(result);
  if (!top) return Image();
  const RigPoints points = InTopFrame(result, layout, *top);
  Image plot(2 * panel_size, panel_size, 3, 0.03f);
  cv::Mat canvas = plot.AsMat();
  // Plan: x right, y up. Side: horizontal distance from the centre, signed by the camera's side
  // (the camera's horizontal direction is +), against height.
  const Eigen::Vector2d camera_side = points.camera.head<2>().norm() > 1e-9 ? Eigen::Vector2d(points.camera.head<2>().normalized())
                                                                             : Eigen::Vector2d(0, -1);
  auto plan = [](const Eigen::Vector3d& q) { return Eigen::Vector2d(q.x(), q.y()); };
  auto side = [&](const Eigen::Vector3d& q) { return Eigen::Vector2d(q.head<2>().dot(camera_side), q.z()); };
  std::vector<Eigen::Vector3d> all = points.balls;
  all.insert(all.end(), points.flashes.begin(), points.flashes.end());
  all.push_back(points.camera);
  for (const auto& corners : points.patches) all.insert(all.end(), corners.begin(), corners.end());
  std::vector<Eigen::Vector2d> plan_extent, side_extent;
  for (const Eigen::Vector3d& q : all) plan_extent.push_back(plan(q)), side_extent.push_back(side(q));
  DrawPanel(MakePanel(canvas, {0, 0}, panel_size, plan_extent), points, plan,
            Format("from above: %zu flash positions", points.flashes.size()), "top board frame: x right, y up");
  DrawPanel(MakePanel(canvas, {panel_size, 0}, panel_size, side_extent), points, side, "from the side",
            "across the table towards the camera; height");
  cv::line(canvas, {panel_size, 0}, {panel_size, panel_size - 1}, cv::Scalar(0.25, 0.25, 0.25));
  return plot;
}

}  // namespace mesocap::app
