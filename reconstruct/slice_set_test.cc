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
      EXPECT_TRUE(WriteImage(dir / file, slice, {.format = PixelFormat::kHalf}).ok());
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

TEST(SliceSet, TheTopViewAloneIsTheTopViewOfTheWholeSet) {
  const fs::path index = WriteSlices(testing::MakeTempDir(), {{2, 35, 5}, {1, 5, 4}, {3, 60, 6}});
  SliceSetOptions as_measured = Options();
  as_measured.btf.mirror_symmetry = false;  // the views keep their own lights only
  auto btf = LoadStatisticalBtf(index, as_measured, nullptr);
  ASSERT_TRUE(btf.ok()) << btf.status().message();
  SliceSetReport report;
  auto top = LoadTopView(index, Options(), &report);
  ASSERT_TRUE(top.ok()) << top.status().message();
  EXPECT_EQ(report.top_board, 1);
  EXPECT_EQ(report.slices_used, 4) << "the other boards' slices are not read";
  EXPECT_TRUE(report.skipped.empty());
  const MeasuredView* whole = nullptr;
  for (const MeasuredView& v : btf->views()) whole = v.view.z() > (whole ? whole->view.z() : -1) ? &v : whole;
  ASSERT_NE(whole, nullptr);
  ASSERT_EQ(top->lights.size(), 4u);
  ASSERT_EQ(top->lights.size(), whole->lights.size());
  EXPECT_TRUE(top->view.isApprox(whole->view));
  for (size_t l = 0; l < top->lights.size(); ++l) {
    EXPECT_TRUE(top->lights[l].isApprox(whole->lights[l]));
    for (int c = 0; c < 3; ++c) EXPECT_EQ(top->statistics[l].pixels[c].values, whole->statistics[l].pixels[c].values);
    EXPECT_EQ(top->statistics[l].bands.size(), whole->statistics[l].bands.size());
  }
  // A set whose top board has too few slices: the error says so.
  const fs::path sparse = WriteSlices(testing::MakeTempDir(), {{1, 5, 2}, {2, 35, 2}});
  EXPECT_FALSE(LoadTopView(sparse, Options()).ok());
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

TEST(SliceStatistics, UndoingAGaussianBlurRestoresASinusoidsAmplitude) {
  // A Gaussian of sigma texels scales a sinusoid of frequency f (cycles a texel) by
  // exp(-2 pi^2 sigma^2 f^2): blurred sinusoids in channels 1 and 2 come back to amplitude 1,
  // channel 0 is left alone, and the gain stops at its cap.
  constexpr int kSize = 32;
  constexpr double kSigma = 0.3, kF1 = 4.0 / kSize, kF2 = 6.0 / kSize;
  const auto damped = [](double f, double sigma) { return std::exp(-2 * M_PI * M_PI * sigma * sigma * f * f); };
  Image image(kSize, kSize, 3);
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      image.at(x, y, 0) = float(damped(kF1, kSigma) * std::cos(2 * M_PI * kF1 * x));
      image.at(x, y, 1) = float(damped(kF1, kSigma) * std::cos(2 * M_PI * kF1 * x));
      image.at(x, y, 2) = float(damped(kF2, kSigma) * std::sin(2 * M_PI * kF2 * y + 0.4));
    }
  Image sharpened = image;
  UndoGaussianBlur(&sharpened, kSigma, /*first_channel=*/1);
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      EXPECT_EQ(sharpened.at(x, y, 0), image.at(x, y, 0));
      EXPECT_NEAR(sharpened.at(x, y, 1), std::cos(2 * M_PI * kF1 * x), 1e-5);
      EXPECT_NEAR(sharpened.at(x, y, 2), std::sin(2 * M_PI * kF2 * y + 0.4), 1e-5);
    }
  // A blur eight times wider would need a gain of 1 / damped(kF2, 8 kSigma) = 55: capped at 3.
  ASSERT_GT(1 / damped(kF2, 8 * kSigma), 50);
  Image capped = image;
  UndoGaussianBlur(&capped, 8 * kSigma, /*first_channel=*/2);
  EXPECT_NEAR(capped.at(0, 0, 2), 3 * image.at(0, 0, 2), 1e-5);
}

TEST(SliceSet, TheBlurUndoneFollowsEachSlicesSizeInThePhoto) {
  // Slices whose chromaticity is a sinusoid at a constant brightness (R + G + B), each 2 photo
  // pixels a texel: a 0.75 px blur is 0.375 texels, so the chromaticities' spread grows by
  // 1 / damped(f) and the brightness stays.
  const fs::path dir = testing::MakeTempDir();
  constexpr int kSize = 16;
  constexpr double kF = 4.0 / kSize, kTexelPx = 2.0;
  Json slices = Json::array();
  for (int k = 0; k < 4; ++k) {
    Image slice(kSize, kSize, 3);
    for (int y = 0; y < kSize; ++y)
      for (int x = 0; x < kSize; ++x) {
        const float wave = float(0.05 * std::cos(2 * M_PI * kF * x + k));
        slice.at(x, y, 0) = 0.3f + wave, slice.at(x, y, 1) = 0.3f - wave, slice.at(x, y, 2) = 0.3f;
      }
    const std::string file = "s" + std::to_string(k) + ".exr";
    ASSERT_TRUE(WriteImage(dir / file, slice, {.format = PixelFormat::kHalf}).ok());
    slices.push_back({{"file", file}, {"board", 0}, {"theta_i_deg", 40}, {"phi_i_deg", 90.0 * k}, {"theta_o_deg", 0},
                      {"phi_o_deg", 0}, {"texel_px", kTexelPx}});
  }
  ASSERT_TRUE(WriteJsonFile(dir / "index.json", {{"format", "mesocap-slices"}, {"slices", slices}}).ok());
  const auto spread = [](const InverseCdf& q) {
    double square = 0;
    for (float v : q.values) square += (v - q.Mean()) * (v - q.Mean());
    return std::sqrt(square / double(q.values.size()));
  };
  SliceSetOptions kept = Options(), undone = Options();
  kept.capture_blur_px = 0;
  undone.capture_blur_px = 0.75;
  kept.remove_chroma_noise = undone.remove_chroma_noise = false;
  SliceSetReport report;
  auto with_blur = LoadStatisticalBtf(dir / "index.json", kept, &report);
  auto without_blur = LoadStatisticalBtf(dir / "index.json", undone, &report);
  ASSERT_TRUE(with_blur.ok() && without_blur.ok());
  const SliceStatistics& a = with_blur->views().front().statistics.front();
  const SliceStatistics& b = without_blur->views().front().statistics.front();
  const double sigma = 0.75 / kTexelPx;
  EXPECT_NEAR(spread(b.pixels[1]) / spread(a.pixels[1]), std::exp(2 * M_PI * M_PI * sigma * sigma * kF * kF), 1e-3);
  EXPECT_NEAR(spread(b.pixels[0]), spread(a.pixels[0]), 1e-6);
}

}  // namespace
}  // namespace mesocap
