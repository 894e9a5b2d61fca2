#include "app/coverage_output.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

namespace mesocap::app {
namespace {

// The camera at the origin looking down +z at a board 1 m away; two balls beside it and a grey
// card facing the camera.
struct SmallRig {
  CalibrationResult calibration;
  RigLayout layout;
  SmallRig() {
    BoardPose board;
    board.id = 0;
    board.found = true;
    board.R = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix();  // its normal toward the camera
    board.t = {0, 0, 1.0};
    calibration.boards.push_back(board);
    layout.boards.push_back({0, 0.2, 0.1, 0, {}});
    for (double x : {-0.3, 0.3}) {
      SphereEstimate ball;
      ball.center_m = {x, 0.0, 0.97};
      ball.radius_m = 0.03;
      calibration.spheres.spheres.push_back(ball);
    }
    GreyCard card;
    card.R = board.R;
    card.t = {0, 0.3, 1.0};
    card.size_m = 0.05;
    card.albedo = 0.18;
    calibration.grey_cards.push_back(card);
  }
};

TEST(FlashUsable, TheFlashMustLightTwoBallHighlightsAndAGreyCard) {
  const SmallRig rig;
  const FlashUsableFn usable = FlashUsableTest(rig.calibration, rig.layout);
  // Beside the camera, half a metre up: both highlights near the balls' centres, the card lit.
  EXPECT_TRUE(usable({0.3, 0.2, 0.2}));
  // Far to the side, level with the card: both highlights usable, but the card is lit edge-on.
  SmallRig no_card;
  no_card.calibration.grey_cards.clear();
  const FlashUsableFn without_card = FlashUsableTest(no_card.calibration, no_card.layout);
  EXPECT_FALSE(usable({3.0, 0.3, 0.97}));
  EXPECT_TRUE(without_card({3.0, 0.3, 0.97}));
  // Beyond the balls: each highlight lies 77 deg from the ball's centre as seen, near its outline.
  EXPECT_FALSE(without_card({0.0, 0.0, 3.0}));
  // Behind the target's plane, off to one side: the card faces away.
  EXPECT_FALSE(usable({0.0, 0.6, 1.5}));
  // A wall between the flash and everything: a board in front of the flash blocks it.
  SmallRig walled;
  BoardPose wall = walled.calibration.boards.front();
  wall.id = 1;
  wall.t = {0.3, 0.2, 0.35};
  walled.calibration.boards.push_back(wall);
  walled.layout.boards.push_back({1, 0.3, 0.1, 0, {}});
  EXPECT_TRUE(usable({0.3, 0.2, 0.2}));
  EXPECT_FALSE(FlashUsableTest(walled.calibration, walled.layout)({0.3, 0.2, 0.2}));
  // A small ball between the flash and one corner of the card's grey area, not its centre: a
  // shadow's edge across the card, which calibration cannot read.
  SmallRig corner;
  SphereEstimate pebble;
  pebble.center_m = {0.0525, 0.2675, 0.919};
  pebble.radius_m = 0.01;
  corner.calibration.spheres.spheres.push_back(pebble);
  EXPECT_FALSE(FlashUsableTest(corner.calibration, corner.layout)({0.3, 0.2, 0.2}));
  corner.calibration.spheres.spheres.back().center_m.x() += 0.05;  // moved off the card's shadow
  EXPECT_TRUE(FlashUsableTest(corner.calibration, corner.layout)({0.3, 0.2, 0.2}));
  // One ball only: never two highlights.
  SmallRig one_ball;
  one_ball.calibration.spheres.spheres.pop_back();
  EXPECT_FALSE(FlashUsableTest(one_ball.calibration, one_ball.layout)({0.3, 0.2, 0.2}));
  // No card located: the power cannot be read anywhere, so no position is worse than another.
  EXPECT_TRUE(without_card({0.3, 0.2, 0.2}));
}

}  // namespace
}  // namespace mesocap::app
