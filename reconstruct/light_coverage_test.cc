#include "reconstruct/light_coverage.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <utility>

#include "core/directions.h"
#include "reconstruct/btf_evaluation.h"
#include "reconstruct/statistical_btf.h"

namespace mesocap {
namespace {

// A board 1 m below the camera, facing it: board x along the camera's x (right in the picture),
// board y toward the top of the picture, z toward the camera.
BoardLights FacingTheCamera() {
  BoardLights b;
  b.R = Eigen::Vector3d(1, -1, -1).asDiagonal();
  b.t = Eigen::Vector3d(0, 0, 1);
  return b;
}

// The sum over targets of the angle to the nearest light, capped: what kSpread shrinks.
double SpreadCost(const BoardLights& board, double cap_deg) {
  double cost = 0;
  for (const Eigen::Vector3d& target : BonnDirections()) {
    double nearest = cap_deg;
    for (const Eigen::Vector3d& light : board.lights) nearest = std::min(nearest, AngleBetweenDeg(light, target));
    cost += nearest;
  }
  return cost;
}

class LightCoverageObjectives : public ::testing::TestWithParam<CoverageObjective> {};

TEST_P(LightCoverageObjectives, ASessionLitFromOneSideIsToldToLightTheOtherSide) {
  BoardLights board = FacingTheCamera();
  for (double theta : {20.0, 40.0, 60.0})
    for (double phi : {-60.0, -20.0, 20.0, 60.0}) board.lights.push_back(DirectionFromAnglesDeg(theta, phi));  // x > 0 only
  CoverageOptions options;
  options.objective = GetParam();
  const CoverageReport before = AssessCoverage({board}, 0, options);
  ASSERT_EQ(before.boards.size(), 1u);
  EXPECT_GT(before.boards[0].targets_covered, 0);
  EXPECT_LT(before.score(), 0.6);
  ASSERT_EQ(before.next.size(), 5u);
  // The first suggestion lies on the unlit side (board x < 0: left of the camera).
  const FlashSuggestion& first = before.next.front();
  EXPECT_GT(first.targets_gained, 0);
  EXPECT_LT(board.LightFrom(first.position_cam).x(), 0);
  EXPECT_NE(first.words.find("left"), std::string::npos) << first.words;
  if (GetParam() == CoverageObjective::kNear) {
    for (size_t k = 1; k < before.next.size(); ++k) EXPECT_LE(before.next[k].targets_gained, before.next[k - 1].targets_gained);
  }
  // Taking the suggested shots covers what they said they would; with kSpread, each shrinks the
  // lights' spread cost.
  int gained = 0;
  for (const FlashSuggestion& s : before.next) {
    const double cost = SpreadCost(board, options.spread_cap_deg);
    board.lights.push_back(board.LightFrom(s.position_cam));
    gained += s.targets_gained;
    if (GetParam() == CoverageObjective::kSpread) {
      EXPECT_LT(SpreadCost(board, options.spread_cap_deg), cost);
    }
  }
  const CoverageReport after = AssessCoverage({board}, 0, options);
  EXPECT_EQ(after.covered, before.covered + gained);
  // kNear aims at the covered share; kSpread at the spread, which raises the share less (5
  // suggestions here: 0.31 -> 0.48).
  EXPECT_GT(after.score(), before.score() + (GetParam() == CoverageObjective::kNear ? 0.2 : 0.15));
}

INSTANTIATE_TEST_SUITE_P(Objectives, LightCoverageObjectives,
                         ::testing::Values(CoverageObjective::kSpread, CoverageObjective::kNear),
                         [](const auto& info) { return info.param == CoverageObjective::kSpread ? "Spread" : "Near"; });

TEST(LightCoverage, ABoardsImagesLendItTheOtherSide) {
  // Lit from x > 0 only; the material holds under the half turn, which takes every light's azimuth
  // round by 180 deg: the reconstruction borrows the images, and guidance counts them.
  BoardLights board = FacingTheCamera();
  for (double theta : {20.0, 40.0, 60.0})
    for (double phi : {-60.0, -20.0, 20.0, 60.0}) board.lights.push_back(DirectionFromAnglesDeg(theta, phi));
  CoverageOptions own, imaged;
  imaged.images[2] = true;
  ASSERT_STREQ(MirrorImages()[2].name, "half_turn");
  const CoverageReport without = AssessCoverage({board}, 0, own), with = AssessCoverage({board}, 0, imaged);
  // (45, 200) is 5 deg from the image of (40, 20) and far from every measured light.
  const std::vector<Eigen::Vector3d> targets = BonnDirections();
  const auto target = std::find_if(targets.begin(), targets.end(), [](const Eigen::Vector3d& t) {
    return AngleBetweenDeg(t, DirectionFromAnglesDeg(45, 200)) < 1;
  });
  ASSERT_NE(target, targets.end());
  const size_t k = size_t(target - targets.begin());
  EXPECT_EQ(without.boards[0].targets[k], TargetState::kUncovered);
  EXPECT_EQ(with.boards[0].targets[k], TargetState::kCovered);
  EXPECT_GT(with.boards[0].targets_covered, without.boards[0].targets_covered);
  EXPECT_LE(with.boards[0].targets_covered, 2 * without.boards[0].targets_covered);
}

TEST(LightCoverage, AFullyLitBoardNeedsNothingMore) {
  BoardLights board = FacingTheCamera();
  board.lights = BonnDirections();
  const CoverageReport report = AssessCoverage({board}, 0);
  EXPECT_DOUBLE_EQ(report.score(), 1.0);
  EXPECT_TRUE(report.next.empty());
}

TEST(LightCoverage, WordsSayWhereTheFlashGoesAsSeenFromTheCamera) {
  const BoardLights top = FacingTheCamera();
  // Camera frame: x right, y down the picture; the board is at z = 1, its normal toward z = 0.
  const std::string right_low = FlashPositionWords(Eigen::Vector3d(1.0, 0, 0.8), top);
  EXPECT_NE(right_low.find("to the right of the camera"), std::string::npos) << right_low;
  EXPECT_NE(right_low.find("low"), std::string::npos) << right_low;
  const std::string top_high = FlashPositionWords(Eigen::Vector3d(0, -0.2, 0.1), top);
  EXPECT_NE(top_high.find("toward the top of the picture"), std::string::npos) << top_high;
  EXPECT_NE(top_high.find("high"), std::string::npos) << top_high;
}

// The rig's 13 boards (top, 4 at 30 deg, 8 at 60 deg; reconstruct/btf_evaluation.h): the 81 Bonn
// views interpolate their rings by incidence, 0 and 15 deg from the top and the 30 deg ring, 30 from
// the 30 deg ring, 45 and 60 between the outer rings, 75 extrapolated (weights -1/2 and 3/2).
// Summed over the Bonn views' incidences (1, 6, 12, 18, 20, 24 views), with the 15 deg views' weight
// w on the 30 deg ring: the top 1 + 6 (1 - w), the 30 deg ring 6 w + 12 + 9 + 12, the 60 deg ring
// 9 + 20 + 36 = 65. In 1 - cos(theta) from the top (the default) w = (1 - cos 15) / (1 - cos 30);
// linearly in theta (the paper) w = 1/2.
TEST(LightCoverage, BoardWeightsAreWhatTheHeldOutViewsBorrowFromEachBoard) {
  std::vector<BoardLights> boards;
  for (const Eigen::Vector3d& view : RigViewDirections()) {
    BoardLights b;
    b.t = -view;  // the camera 1 m along the board's view direction
    boards.push_back(b);
  }
  const double even_w = (1 - std::cos(DegToRad(15))) / (1 - std::cos(DegToRad(30)));
  for (const auto& [even_at_pole, w] : {std::pair{true, even_w}, std::pair{false, 0.5}}) {
    SCOPED_TRACE(even_at_pole ? "1 - cos(theta) from the top" : "linear in theta");
    const std::vector<double> weights = BoardWeights(boards, even_at_pole);
    ASSERT_EQ(weights.size(), 13u);
    const double scale = 13.0 / (1 + 6 + 33 + 65);
    EXPECT_NEAR(weights[0], (1 + 6 * (1 - w)) * scale, 1e-9);
    double ring30 = 0, ring60 = 0;
    for (int b = 1; b <= 4; ++b) ring30 += weights[size_t(b)];
    for (int b = 5; b <= 12; ++b) ring60 += weights[size_t(b)];
    EXPECT_NEAR(ring30, (6 * w + 33) * scale, 1e-9);
    EXPECT_NEAR(ring60, 65 * scale, 1e-9);
  }
  // One board: every view borrows from it alone.
  EXPECT_EQ(BoardWeights({boards[5]}), std::vector<double>{1.0});
}

TEST(LightCoverage, NoBoardsGiveAnEmptyReport) {
  EXPECT_TRUE(AssessCoverage({}, 0).boards.empty());
  EXPECT_TRUE(AssessCoverage({FacingTheCamera()}, 3).boards.empty());
}

}  // namespace
}  // namespace mesocap
