#include "core/rig_layout.h"

#include <gtest/gtest.h>

namespace mesocap {
namespace {

Json GoodLayout() {
  RigLayout l;
  LayoutBoard board;
  board.id = 0, board.size_m = 0.1, board.patch_m = 0.05;
  LayoutTag tag;
  tag.id = 3, tag.size_m = 0.02;
  tag.corners_m = {Eigen::Vector2d(0, 0), Eigen::Vector2d(0.02, 0), Eigen::Vector2d(0.02, 0.02), Eigen::Vector2d(0, 0.02)};
  board.tags.push_back(tag);
  l.boards.push_back(board);
  board.id = 7;
  l.grey_cards.push_back(board);
  l.sphere_count = 2, l.sphere_radius_m = 0.028;
  l.grey_card_albedo = 0.18;
  l.checker_cols = 9, l.checker_rows = 6, l.checker_square_m = 0.02;
  return l.ToJson();
}

void ExpectRefused(const Json& j, const std::string& fragment) {
  auto l = RigLayout::FromJson(j);
  ASSERT_FALSE(l.ok()) << "accepted: " << j.dump();
  EXPECT_NE(l.status().message().find(fragment), std::string::npos) << l.status().message();
}

TEST(RigLayout, RoundTrips) {
  auto l = RigLayout::FromJson(GoodLayout());
  ASSERT_TRUE(l.ok()) << l.status().message();
  EXPECT_EQ(l->ToJson(), GoodLayout());
}

TEST(RigLayout, EveryFieldIsCheckedAndNamed) {
  Json j = GoodLayout();
  j["spheres"]["count"] = 0;  // once an assertion in the sphere search
  ExpectRefused(j, "spheres.count = 0 is outside [1, 16]");
  j = GoodLayout();
  j["spheres"]["radius_m"] = "big";
  ExpectRefused(j, "spheres.radius_m must be a number, not string");
  j = GoodLayout();
  j["boards"] = Json::array();
  ExpectRefused(j, "boards has 0 entries");
  j = GoodLayout();
  j["boards"][0]["tags"][0]["id"] = 9999;
  ExpectRefused(j, "boards[0].tags[0].id = 9999 is outside [0, 586]");
  j = GoodLayout();
  j["boards"][0]["tags"][0]["corners_m"].erase(3);
  ExpectRefused(j, "boards[0].tags[0].corners_m has 3 entries; exactly 4 expected");
  j = GoodLayout();
  j["boards"][0]["patch_m"] = 0.5;
  ExpectRefused(j, "boards[0].patch_m = 0.5 is outside");
  j = GoodLayout();
  j["grey_cards"].erase("albedo");
  ExpectRefused(j, "grey_cards.albedo is missing");
  j = GoodLayout();
  j["checkerboard"]["cols"] = 1e12;
  ExpectRefused(j, "checkerboard.cols must be an integer");
  j = GoodLayout();
  j["tag_family"] = "tag25h9";
  ExpectRefused(j, "tag_family 'tag25h9' is not supported");
  ExpectRefused(Json::array(), "must be a JSON object");
  ExpectRefused(Json("text"), "must be a JSON object");
}

}  // namespace
}  // namespace mesocap
