// Calibration of a rendered session against the virtual rig's ground truth (truth.json is
// read by the test only; the calibration never sees it).
#include "calib/calibrate.h"

#include <gtest/gtest.h>

#include "calib/truth_comparison.h"
#include "capture/simulate.h"
#include "tests/testing.h"

namespace mesocap {
namespace {

void CheckSessionAgainstTruth(const std::string& material, uint64_t seed) {
  const auto dir = testing::MakeTempDir();
  SimulateOptions sim;
  sim.rig.material = material;
  sim.rig.seed = seed;
  sim.rig.shots = 14;
  sim.rig.calib_shots = 0;
  sim.out = dir / "session";
  ASSERT_TRUE(SimulateSession(sim).ok());
  auto scene = MakeRigScene(sim.rig);
  ASSERT_TRUE(scene.ok());
  auto truth = ReadJsonFile(sim.out / "truth.json");
  ASSERT_TRUE(truth.ok());

  CalibrateOptions options;
  options.session = sim.out;
  // The true intrinsics isolate these steps; calib/intrinsics_test scores the intrinsics.
  auto result = CalibrateSession(options, LayoutOf(*scene), scene->camera);
  ASSERT_TRUE(result.ok()) << result.status().message();
  const CalibrationScore score = ScoreAgainstTruth(*result, *truth);
  std::printf("%s\n%s\n", result->Brief().c_str(), score.Brief().c_str());
  for (const auto& r : result->rejected) std::printf("  rejected: %s\n", r.c_str());

  // Issue 4's targets.
  EXPECT_GE(score.boards_posed, 12);
  EXPECT_LT(score.board_rotation_max_deg, 0.3);
  EXPECT_LT(score.board_translation_max_mm, 1.0);
  EXPECT_EQ(score.balls_found, score.balls_total);
  EXPECT_GE(score.shots_with_light, score.shots_total - 2);
  EXPECT_LT(score.light_direction_max_deg, 2.0);
  EXPECT_LT(score.light_distance_median_pct, 2.0);
  EXPECT_LT(score.power_median_pct, 3.0);
  EXPECT_GE(score.power_shots, score.shots_total / 2);
  EXPECT_LT(score.ball_centre_max_mm, 2.0);
  EXPECT_LT(score.light_direction_median_deg, 0.5);
}

// Two materials and two seeds: different textures under the tags and balls, different poses and lights.
TEST(Calibrate, WeaveSessionMatchesTruth) { CheckSessionAgainstTruth("weave", 21); }
TEST(Calibrate, StonesSessionMatchesTruth) { CheckSessionAgainstTruth("stones", 7); }

}  // namespace
}  // namespace mesocap
