#include "calib/truth_comparison.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/directions.h"
#include "core/median.h"

namespace mesocap {

Json CalibrationScore::ToJson() const {
  return {{"fx_error_pct", fx_error_pct}, {"fy_error_pct", fy_error_pct}, {"boards_posed", boards_posed},
          {"boards_total", boards_total}, {"board_rotation_max_deg", board_rotation_max_deg},
          {"board_translation_max_mm", board_translation_max_mm}, {"balls_found", balls_found},
          {"balls_total", balls_total}, {"ball_centre_max_mm", ball_centre_max_mm},
          {"shots_with_light", shots_with_light}, {"shots_total", shots_total},
          {"light_direction_median_deg", light_direction_median_deg},
          {"light_direction_max_deg", light_direction_max_deg},
          {"light_distance_median_pct", light_distance_median_pct}, {"power_median_pct", power_median_pct},
          {"power_shots", power_shots}};
}

std::string CalibrationScore::Brief() const {
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "fx %.3f%% fy %.3f%%; boards %d/%d, rotation <= %.3f deg, translation <= %.3f mm; balls %d/%d, "
                "centre <= %.2f mm; flash %d/%d, direction median %.3f max %.3f deg, distance median %.2f%%, "
                "power median %.2f%%",
                fx_error_pct, fy_error_pct, boards_posed, boards_total, board_rotation_max_deg, board_translation_max_mm,
                balls_found, balls_total, ball_centre_max_mm, shots_with_light, shots_total, light_direction_median_deg,
                light_direction_max_deg, light_distance_median_pct, power_median_pct);
  return buf;
}

CalibrationScore ScoreAgainstTruth(const CalibrationResult& r, const Json& truth) {
  CalibrationScore s;
  const Eigen::Matrix3d K = Matrix3dFromJson(truth.at("camera").at("K"));
  s.fx_error_pct = 100 * std::abs(r.camera.K(0, 0) - K(0, 0)) / K(0, 0);
  s.fy_error_pct = 100 * std::abs(r.camera.K(1, 1) - K(1, 1)) / K(1, 1);
  const Json& boards = truth.at("boards");
  s.boards_total = int(boards.size());
  for (size_t b = 0; b < r.boards.size() && b < boards.size(); ++b) {
    if (!r.boards[b].found) continue;
    ++s.boards_posed;
    const Eigen::Matrix3d dR = r.boards[b].R * Matrix3dFromJson(boards[b].at("R")).transpose();
    s.board_rotation_max_deg =
        std::max(s.board_rotation_max_deg, RadToDeg(std::acos(std::clamp((dR.trace() - 1) / 2, -1.0, 1.0))));
    s.board_translation_max_mm =
        std::max(s.board_translation_max_mm, 1000 * (r.boards[b].t - Vector3dFromJson(boards[b].at("t"))).norm());
  }
  s.balls_total = int(truth.at("spheres").size());
  s.balls_found = int(r.spheres.spheres.size());
  for (const auto& est : r.spheres.spheres) {
    double best = 1e9;
    for (const auto& t : truth.at("spheres"))
      best = std::min(best, 1000 * (est.center_m - Vector3dFromJson(t.at("center_m"))).norm());
    s.ball_centre_max_mm = std::max(s.ball_centre_max_mm, best);
  }
  const Eigen::Vector3d centre = Vector3dFromJson(boards[0].at("t"));
  const Json& shots = truth.at("shots");
  s.shots_total = int(r.shots.size());
  double truth_power_mean = 0;
  for (size_t k = 0; k < r.shots.size() && k < shots.size(); ++k)
    if (r.shots[k].light.ok) truth_power_mean += shots[k].at("power").get<double>(), ++s.shots_with_light;
  truth_power_mean /= std::max(1, s.shots_with_light);
  std::vector<double> dir, dist, power;
  for (size_t k = 0; k < r.shots.size() && k < shots.size(); ++k) {
    const ShotCalibration& sc = r.shots[k];
    if (!sc.light.ok) continue;
    const Eigen::Vector3d t = Vector3dFromJson(shots[k].at("light_m")) - centre, e = sc.light.light_m - centre;
    dir.push_back(AngleBetweenDeg(t, e));
    dist.push_back(100 * std::abs(e.norm() - t.norm()) / t.norm());
    if (sc.flag.empty()) {
      const double truth_rel = shots[k].at("power").get<double>() / truth_power_mean;
      power.push_back(100 * std::abs(sc.power - truth_rel) / truth_rel);
    }
  }
  s.light_direction_median_deg = UpperMedian(dir);
  s.light_direction_max_deg = dir.empty() ? 0 : *std::max_element(dir.begin(), dir.end());
  s.light_distance_median_pct = UpperMedian(dist);
  s.power_median_pct = UpperMedian(power);
  s.power_shots = int(power.size());
  return s;
}

}  // namespace mesocap
