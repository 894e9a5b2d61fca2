// The synthesis quality measures against closed-form answers: the map usage of maps built by hand,
// and the Laplacian/gradient distance's invariants.
#include <gtest/gtest.h>

#include "synth/synth_quality.h"
#include "synth/synth_test_support.h"
#include "tests/testing.h"

namespace mesocap {
namespace {

SynthMap Identity(int size) {
  SynthMap map(size, size, size, size, "test");
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) map.Set(x, y, x + 0.5f, y + 0.5f, 0, 0);
  return map;
}

TEST(MapUsage, TheSampleItselfUsesEveryTexelOnceInOneRegion) {
  const MapUsage u = MeasureMapUsage(Identity(20));
  EXPECT_EQ(u.repeat_share, 0.0);
  EXPECT_EQ(u.used_share, 1.0);
  EXPECT_EQ(u.largest_coherent_region, 400);
}

TEST(MapUsage, OneTexelEverywhereRepeatsAllButTheFirst) {
  SynthMap map(10, 8, 16, 16, "test");
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 10; ++x) map.Set(x, y, 3.5f, 7.5f, 0, 0);
  const MapUsage u = MeasureMapUsage(map);
  EXPECT_DOUBLE_EQ(u.repeat_share, 79.0 / 80.0);
  EXPECT_DOUBLE_EQ(u.used_share, 1.0 / 256.0);
  EXPECT_EQ(u.largest_coherent_region, 1);
}

TEST(MapUsage, StretchedColumnsRepeatAndTwoBlocksAreTwoRegions) {
  // Left half: the sample's columns each used twice (a 2x horizontal stretch); right half: a
  // verbatim 8 x 16 block.
  SynthMap map(16, 16, 32, 32, "test");
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x)
      map.Set(x, y, x < 8 ? x / 2 + 0.5f : x + 10.5f, y + 0.5f, 0, 0);
  const MapUsage u = MeasureMapUsage(map);
  EXPECT_DOUBLE_EQ(u.repeat_share, 16.0 * 4 / 256);  // x = 1, 3, 5, 7 of every row
  EXPECT_EQ(u.largest_coherent_region, 8 * 16);
  EXPECT_DOUBLE_EQ(u.used_share, (4.0 * 16 + 8 * 16) / (32 * 32));
}

TEST(LaplacianGradientDistance, ZeroForTheSameImageAndBlindToAnOffsetButNotToContrast) {
  const Image a = testing::NoiseImage(48, 40, 2, testing::SeedFromTestName());
  Image offset = a, contrast = a;
  for (size_t i = 0; i < a.size(); ++i) offset.data()[i] += 0.3f, contrast.data()[i] *= 2;
  EXPECT_EQ(LaplacianGradientDistance(a, a), 0.0);
  EXPECT_LT(LaplacianGradientDistance(a, offset), 1e-6);  // every band is a difference
  const double d = LaplacianGradientDistance(a, contrast);
  EXPECT_GT(d, 0.02);
  EXPECT_DOUBLE_EQ(d, LaplacianGradientDistance(contrast, a));
}

}  // namespace
}  // namespace mesocap
