#include "core/slice_index.h"

#include <gtest/gtest.h>

#include <fstream>

#include "core/json.h"
#include "tests/testing.h"

namespace mesocap {
namespace {

Json Entry(const std::string& file, double theta_i, double phi_i) {
  return {{"file", file}, {"board", 1}, {"theta_i_deg", theta_i}, {"phi_i_deg", phi_i}, {"theta_o_deg", 30}, {"phi_o_deg", 0}};
}

StatusOr<SliceIndex> ReadWith(const std::filesystem::path& dir, const Json& entry) {
  const Json index = {{"format", "mesocap-slices"}, {"slices", {Entry("a.exr", 10, 20), entry}}};
  std::ofstream(dir / "index.json") << index.dump();
  return ReadSliceIndex(dir / "index.json");
}

TEST(SliceIndex, ReadsAndNormalisesAzimuths) {
  const auto dir = testing::MakeTempDir();
  auto index = ReadWith(dir, Entry("b/c.exr", 45, -40));
  ASSERT_TRUE(index.ok()) << index.status().message();
  ASSERT_EQ(index->slices.size(), 2u);
  EXPECT_EQ(index->format, "mesocap-slices");
  EXPECT_EQ(index->slices[1].file, dir / "b/c.exr");
  EXPECT_DOUBLE_EQ(index->slices[1].phi_i_deg, 320);
  EXPECT_EQ(index->slices[1].board, 1);
  index = ReadWith(dir, Entry("c.exr", 45, 400));
  ASSERT_TRUE(index.ok());
  EXPECT_NEAR(index->slices[1].phi_i_deg, 40, 1e-9);
  EXPECT_EQ(index->slices[1].light_distance_m, 0) << "absent: 0";
  Json with_distance = Entry("c.exr", 45, 0);
  with_distance["light_distance_m"] = 1.25;
  index = ReadWith(dir, with_distance);
  ASSERT_TRUE(index.ok());
  EXPECT_EQ(index->slices[1].light_distance_m, 1.25);
}

TEST(SliceIndex, RefusesOutOfRangeAnglesAndPathsLeavingTheFolder) {
  const auto dir = testing::MakeTempDir();
  const std::pair<Json, std::string> bad[] = {
      {Entry("c.exr", 1e300, 0), "slices[1].theta_i_deg = 1e+300 is outside [0, 90]"},
      {Entry("c.exr", -1, 0), "slices[1].theta_i_deg = -1"},
      {Entry("/etc/passwd", 10, 0), "slices[1].file = \"/etc/passwd\" must be a relative path"},
      {Entry("../x.exr", 10, 0), "must not leave its folder"},
      {Entry("", 10, 0), "must be a relative path"},
      {Json::array(), "slices[1] must be a JSON object"},
      {{{"file", "c.exr"}}, "slices[1].theta_i_deg is missing"},
      {[] {
         Json e = Entry("c.exr", 10, 0);
         e["light_distance_m"] = "far";
         return e;
       }(),
       "slices[1].light_distance_m must be a number"},
  };
  for (const auto& [entry, fragment] : bad) {
    auto index = ReadWith(dir, entry);
    ASSERT_FALSE(index.ok()) << entry.dump();
    EXPECT_NE(index.status().message().find("index.json: "), std::string::npos) << index.status().message();
    EXPECT_NE(index.status().message().find(fragment), std::string::npos) << index.status().message();
  }
  std::ofstream(dir / "index.json") << R"({"slices": []})";
  EXPECT_FALSE(ReadSliceIndex(dir / "index.json").ok());
}

// The resampling's skipped (board, shot) pairs are read typed; a malformed one is an error naming
// its field, not a row of defaults.
TEST(SliceIndex, ReadsTheSkippedPairsAndRefusesAMalformedOne) {
  const auto dir = testing::MakeTempDir();
  Json index = {{"format", "mesocap-slices"},
                {"slices", {Entry("a.exr", 10, 20)}},
                {"skipped", {{{"board", 3}, {"shot", "shots/shot_0004.jpg"}, {"reason", "12.5% of the patch saturated"}}}}};
  std::ofstream(dir / "index.json") << index.dump();
  auto read = ReadSliceIndex(dir / "index.json");
  ASSERT_TRUE(read.ok()) << read.status().message();
  ASSERT_EQ(read->skipped.size(), 1u);
  EXPECT_EQ(read->skipped[0].board, 3);
  EXPECT_EQ(read->skipped[0].shot, "shots/shot_0004.jpg");
  EXPECT_EQ(read->skipped[0].reason, "12.5% of the patch saturated");
  index["skipped"][0].erase("reason");
  std::ofstream(dir / "index.json") << index.dump();
  read = ReadSliceIndex(dir / "index.json");
  ASSERT_FALSE(read.ok());
  EXPECT_NE(read.status().message().find("skipped[0].reason"), std::string::npos) << read.status().message();
}

}  // namespace
}  // namespace mesocap
