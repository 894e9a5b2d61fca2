// Scores a calibration against a virtual session's truth.json (same keys): the figures issue 4
// names, computed once for the tests, the demo and the report.
#pragma once

#include <string>

#include "calib/calibrate.h"
#include "core/json.h"

namespace mesocap {

struct CalibrationScore {
  double fx_error_pct = 0, fy_error_pct = 0;
  int boards_posed = 0, boards_total = 0;
  double board_rotation_max_deg = 0, board_translation_max_mm = 0;
  int balls_found = 0, balls_total = 0;
  double ball_centre_max_mm = 0;
  int shots_with_light = 0, shots_total = 0;
  double light_direction_median_deg = 0, light_direction_max_deg = 0;  // seen from the top board
  double light_distance_median_pct = 0;
  double power_median_pct = 0;  // relative powers (mean 1) against truth's, shots not flagged
  int power_shots = 0;
  Json ToJson() const;
  std::string Brief() const;
};

// `truth`: the parsed truth.json of the session the result came from.
CalibrationScore ScoreAgainstTruth(const CalibrationResult& result, const Json& truth);

}  // namespace mesocap
