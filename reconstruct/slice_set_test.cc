// Loading a session's slices: which board gives the top view, and what is said when no board is
// seen head-on or none has lights enough.
#include "reconstruct/slice_set.h"

#include <gtest/gtest.h>

#include <optional>
#include <random>

#include "core/image_io.h"
#include "core/json.h"
#include "tests/testing.h"

namespace mesocap {
namespace {

namespace fs = std::filesystem;

struct Board {
  int id;
  double theta_o_deg;
  int lights;
};

// A mesocap-slices index of noisy 16x16 slices: per board, `lights` lights on a ring.
fs::path WriteSlices(const fs::path& dir, const std::vector<Board>& boards, std::optional<bool> chroma_subsampled = {}) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0.2f, 0.8f);
  Json slices = Json::array();
  for (const Board& b : boards)
    for (int k = 0; k < b.lights; ++k) {
      Image slice(16, 16, 3);
      for (size_t i = 0; i < slice.size(); ++i) slice.data()[i] = u(rng);
      const std::string file = "b" + std::to_string(b.id) + "_" + std::to_string(k) + ".exr";
      EXPECT_TRUE(WriteImage(dir / file, slice).ok());
      slices.push_back({{"file", file}, {"board", b.id}, {"theta_i_deg", 40}, {"phi_i_deg", 360.0 * k / b.lights},
                        {"theta_o_deg", b.theta_o_deg}, {"phi_o_deg", 90}});
    }
  Json index = {{"format", "mesocap-slices"}, {"slices", slices}};
  if (chroma_subsampled) index["chroma_subsampled_shots"] = *chroma_subsampled;
  EXPECT_TRUE(WriteJsonFile(dir / "index.json", index).ok());
  return dir / "index.json";
}

SliceSetOptions Options() {
  SliceSetOptions options;
  options.size = 16;
  return options;
}

TEST(SliceSet, TheTopViewIsTheMostHeadOnBoardWithLightsEnough) {
  const fs::path index = WriteSlices(testing::MakeTempDir(), {{1, 5, 4}, {2, 35, 5}});
  SliceSetReport report;
  auto btf = LoadStatisticalBtf(index, Options(), &report);
  ASSERT_TRUE(btf.ok()) << btf.status().message();
  EXPECT_EQ(report.top_board, 1);
  EXPECT_EQ(report.views, 2);
  EXPECT_TRUE(report.warnings.empty());
}

TEST(SliceSet, ASessionWithNoHeadOnBoardIsWarnedOf) {
  // The head-on board saw two lights only: the 35 deg board gives the top view, with a warning.
  const fs::path index = WriteSlices(testing::MakeTempDir(), {{1, 5, 2}, {2, 35, 5}});
  SliceSetReport report;
  auto btf = LoadStatisticalBtf(index, Options(), &report);
  ASSERT_TRUE(btf.ok()) << btf.status().message();
  EXPECT_EQ(report.top_board, 2);
  ASSERT_EQ(report.warnings.size(), 1u);
  EXPECT_NE(report.warnings[0].find("no top view: the most head-on board with 3 or more slices, board 2, is seen 35 deg"),
            std::string::npos)
      << report.warnings[0];
  bool named = false;
  for (const std::string& s : report.skipped) named |= s == "board 1: fewer than 3 usable slices, view not used";
  EXPECT_TRUE(named);
}

TEST(SliceSet, NoBoardWithThreeLightsIsAnError) {
  const fs::path index = WriteSlices(testing::MakeTempDir(), {{1, 5, 2}, {2, 35, 2}});
  SliceSetReport report;
  auto btf = LoadStatisticalBtf(index, Options(), &report);
  ASSERT_FALSE(btf.ok());
  EXPECT_NE(btf.status().message().find("index.json: no board has 3 or more slices"), std::string::npos)
      << btf.status().message();
}

TEST(SliceSet, ShotsWithColourAtHalfResolutionTakeTheColourFromTheTopView) {
  for (const std::optional<bool> subsampled : {std::optional<bool>(), std::optional(false), std::optional(true)}) {
    const fs::path index = WriteSlices(testing::MakeTempDir(), {{1, 5, 4}, {2, 35, 5}}, subsampled);
    for (const std::optional<bool> forced : {std::optional<bool>(), std::optional(false), std::optional(true)}) {
      SliceSetOptions options = Options();
      options.btf.chromaticity_from_top_view = !subsampled.value_or(false);  // overridden by the index or `forced`
      options.chroma_from_top = forced;
      SliceSetReport report;
      auto btf = LoadStatisticalBtf(index, options, &report);
      ASSERT_TRUE(btf.ok()) << btf.status().message();
      const bool want = forced.value_or(subsampled.value_or(false));
      EXPECT_EQ(report.chroma_from_top, want);
      EXPECT_EQ(btf->options().chromaticity_from_top_view, want);
    }
  }
}

TEST(SliceSet, ANonBooleanChromaSubsampledFieldIsAnErrorNamingIt) {
  const fs::path dir = testing::MakeTempDir();
  const fs::path index = WriteSlices(dir, {{1, 5, 4}});
  auto json = ReadJsonFile(index);
  ASSERT_TRUE(json.ok());
  (*json)["chroma_subsampled_shots"] = "yes";
  ASSERT_TRUE(WriteJsonFile(index, *json).ok());
  auto btf = LoadStatisticalBtf(index, Options(), nullptr);
  ASSERT_FALSE(btf.ok());
  EXPECT_NE(btf.status().message().find("chroma_subsampled_shots"), std::string::npos) << btf.status().message();
}

}  // namespace
}  // namespace mesocap
