// Loading a session's slices: which board gives the top view, and what is said when no board is
// seen head-on or none has lights enough.
#include "reconstruct/slice_set.h"

#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <random>

#include "core/image_io.h"
#include "core/json.h"
#include "reconstruct/quantiles.h"
#include "reconstruct/slice_statistics.h"
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

// Two slices of one view at nearby lights: the same signal, independent noise. Their difference
// measures the noise, and taking its variance out brings the noisy slice's chromaticity
// statistics back to the clean slice's; the brightness channel (0) is left as it was. The colour
// varies less than the noise, as stones' does in a JPEG shot.
TEST(SliceStatistics, TheNoiseOfTwoSlicesIsTakenOutOfTheChromaticities) {
  constexpr int kSize = 64;
  Image clean(kSize, kSize, 3), a(kSize, kSize, 3), b(kSize, kSize, 3);
  std::mt19937 rng(7);
  std::normal_distribution<float> noise(0.0f, 0.01f);
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      const float signal[3] = {0.5f + 0.2f * float(x) / kSize, 0.33f + 0.005f * std::sin(float(x) * 0.4f),
                               0.33f + 0.005f * std::cos(float(y) * 0.3f)};
      for (int c = 0; c < 3; ++c) {
        clean.at(x, y, c) = signal[c];
        a.at(x, y, c) = signal[c] + noise(rng);
        b.at(x, y, c) = signal[c] + noise(rng);
      }
    }
  const SliceStatistics truth = ComputeSliceStatistics(clean);
  const SliceStatistics noisy = ComputeSliceStatistics(a);
  SliceStatistics denoised = noisy;
  RemoveNoiseVariance(&denoised, ComputeSliceStatistics(NoiseDifference(a, b)), /*first_channel=*/1);
  EXPECT_EQ(denoised.pixels[0].values, noisy.pixels[0].values);
  for (int c = 1; c < 3; ++c) {
    const double before = WassersteinDistance(noisy.pixels[size_t(c)], truth.pixels[size_t(c)]);
    const double after = WassersteinDistance(denoised.pixels[size_t(c)], truth.pixels[size_t(c)]);
    EXPECT_LT(after, 0.3 * before) << "channel " << c << ": " << before << " -> " << after;
    const auto spread = [](const InverseCdf& q) {  // standard deviation
      double square = 0;
      for (float v : q.values) square += (v - q.Mean()) * (v - q.Mean());
      return std::sqrt(square / double(q.values.size()));
    };
    EXPECT_NEAR(spread(denoised.pixels[size_t(c)]) / spread(truth.pixels[size_t(c)]), 1.0, 0.2) << "channel " << c;
    const double band_before = WassersteinDistance(noisy.band(c, 0), truth.band(c, 0));
    const double band_after = WassersteinDistance(denoised.band(c, 0), truth.band(c, 0));
    EXPECT_LT(band_after, 0.5 * band_before) << "channel " << c << ", finest band";
  }
}

}  // namespace
}  // namespace mesocap
