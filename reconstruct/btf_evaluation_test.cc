// The acceptance test: on every virtual-rig material, the statistical reconstruction
// beats both of the paper's baselines on pixel Wasserstein distance for at least 80% of the
// held-out direction pairs. Small slices and an even subset of the 5832 held-out pairs keep it
// fast; `mesocap evaluate` runs the full grid. The truth averages each texel's footprint (3x3
// samples) as a camera pixel would: point-sampled 1 mm texels alias the corduroy's 3 mm wales
// into view-dependent moire that no method could predict (72.9% instead of 82% on corduroy).
// Colour is scored too: saturation and chromaticity against the truth.
#include "reconstruct/btf_evaluation.h"

#include <cmath>

#include <gtest/gtest.h>

#include "capture/btf_render.h"
#include "capture/true_btf_renderer.h"
#include "core/directions.h"

namespace mesocap {
namespace {

class EvaluateMaterial : public ::testing::TestWithParam<std::string> {};

TEST_P(EvaluateMaterial, BeatsBothBaselinesOnWassersteinForMostHeldOutPairs) {
  auto material = Material::Create(GetParam());
  ASSERT_TRUE(material.ok());
  // Area-averaged texels (3x3 samples): point samples alias the 3 mm corduroy wales.
  TrueBtfRequest grid;
  grid.size = 64;
  grid.samples_per_axis = 3;
  const TrueBtfRenderer renderer(*material, grid);
  const TrueSliceFn truth = [&](const Eigen::Vector3d& light, const Eigen::Vector3d& view) {
    return renderer.Render(light, view);
  };
  BtfEvaluationOptions options;
  options.max_pairs = 240;
  auto eval = EvaluateStatisticalBtf(truth, options);
  ASSERT_TRUE(eval.ok()) << eval.status().message();
  EXPECT_EQ(eval->pairs.size(), 240u);
  std::printf("%s: %s\n", GetParam().c_str(), eval->Brief().c_str());
  EXPECT_GE(eval->FractionBeatingBoth(&PairScore::wasserstein_pixels), 0.8);
  // Colour (issue 12), histograms matched in brightness and chromaticity: the 95th-percentile
  // saturation within 5% of the truth's at the median. Within 15% on all but a few pairs: the
  // misses are grazing mirror pairs whose white highlight none of the views measured (2-6 of 240
  // here; 6-18 for the top-view baseline).
  EXPECT_LE(eval->MedianSaturationError()[0], 0.05);
  int off_by_more = 0;
  for (const PairScore& p : eval->pairs) off_by_more += std::abs(p.saturation_ratio[0] - 1) > 0.15;
  EXPECT_LE(off_by_more, 8);
  EXPECT_GE(eval->FractionBeatingBoth(&PairScore::wasserstein_chromaticity), 0.5);
}

// The true-mean diagnostic on a BTF that is one texture times a scalar of light and view: the
// statistics of every slice are the texture's up to scale, so the reconstruction has the right
// distributions up to its mean, and scaled to the truth's means it matches the truth; without
// the oracle, the interpolated mean (light and view interpolation of a non-linear factor) is off.
TEST(EvaluateAtTrueMean, LeavesOnlyTheShapeOfTheDistributionsToBeScored) {
  const TrueSliceFn truth = [](const Eigen::Vector3d& light, const Eigen::Vector3d& view) {
    const double factor = (0.2 + light.z() * light.z()) * (1 + 3 * std::pow(1 - view.z(), 2)) * (1 + 0.5 * light.dot(view));
    Image slice(32, 32, 3);
    for (int y = 0; y < 32; ++y)
      for (int x = 0; x < 32; ++x)
        for (int c = 0; c < 3; ++c)
          slice.at(x, y, c) = float(factor * (0.3 + 0.2 * std::sin(0.9 * x + 0.4 * y + c) + 0.02 * ((x * 7 + y * 3) % 5)) *
                                    (1.0 - 0.2 * c));
    return slice;
  };
  BtfEvaluationOptions options;
  for (size_t k = 0; k < BonnDirections().size(); k += 2) options.input_lights.push_back(BonnDirections()[k]);
  options.max_pairs = 24;
  auto as_reconstructed = EvaluateStatisticalBtf(truth, options);
  options.statistical_at_true_mean = true;
  auto at_true_mean = EvaluateStatisticalBtf(truth, options);
  ASSERT_TRUE(as_reconstructed.ok() && at_true_mean.ok());
  const auto before = as_reconstructed->Median(&PairScore::wasserstein_pixels);
  const auto after = at_true_mean->Median(&PairScore::wasserstein_pixels);
  std::printf("median pixel W1: reconstructed %.5f, at the true mean %.5f (top view %.5f)\n", before[0], after[0], before[1]);
  EXPECT_LT(after[0], 0.2 * before[0]);
  EXPECT_EQ(after[1], before[1]);  // the baselines are not touched
  EXPECT_EQ(after[2], before[2]);
}

INSTANTIATE_TEST_SUITE_P(Materials, EvaluateMaterial, ::testing::Values("weave", "stones", "corduroy"));

}  // namespace
}  // namespace mesocap
