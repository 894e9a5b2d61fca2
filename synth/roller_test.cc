#include "synth/roller.h"

#include <random>

#include <gtest/gtest.h>

#include "synth/synth_quality.h"
#include "synth/synth_test_support.h"
#include "tests/testing.h"

namespace mesocap {
namespace {

TEST(Roller, WeaveTilesWrapSeamlesslyAndTheOutputHasNoVisibleSeams) {
  const Exemplar e = testing::VirtualRigExemplar("weave");
  RollerOptions o;
  o.width = o.height = 256;
  o.tiles = 3;
  RollerReport rep;
  auto tiles = AnalyseRoller(e.features, Luminance(e.preview), o, &rep);
  ASSERT_TRUE(tiles.ok()) << tiles.status().message();
  EXPECT_FALSE(rep.frequency_fallback) << rep.fallback_reason;
  ASSERT_EQ(tiles->tiles.size(), 3u);
  EXPECT_EQ(rep.tiles_made, 3);  // what report.json records as made
  const SynthMap map = RollTiles(*tiles, e.width, e.height, o.width, o.height, o.seed);
  ASSERT_TRUE(ValidateMap(map).ok());
  for (int k = 0; k < int(e.slices.size()); ++k) {
    const Image slice = *e.ReadSlice(k);
    // Each tile repeated next to itself: the wrap-around edges count.
    for (int t = 0; t < 3; ++t) {
      const SynthMap one = RollTiles({tiles->tile_width, tiles->tile_height, {tiles->tiles[t]}}, e.width, e.height,
                                     tiles->tile_width, tiles->tile_height, 1);
      const SeamMeasure wrap = MeasureSeams(one, ApplyMapToImage(one, slice), slice, /*wrap=*/true);
      EXPECT_LE(wrap.ratio(), 1.2) << "slice " << k << " tile " << t;
    }
    const Image out = ApplyMapToImage(map, slice);
    const SeamMeasure s = MeasureSeams(map, out, slice);
    EXPECT_LE(s.ratio(), 1.2) << "slice " << k;
    const SynthMap random = RandomTilingMap(e.width, e.height, o.width, o.height, tiles->tile_width, 5);
    EXPECT_LT(s.ratio(), 0.8 * MeasureSeams(random, ApplyMapToImage(random, slice), slice).ratio()) << "slice " << k;
  }
}

TEST(Roller, NoiseHasNoDominantFrequencyAndFallsBackToTheStatedDefault) {
  std::mt19937 rng(testing::SeedFromTestName());
  std::uniform_real_distribution<float> u(0, 1);
  Image noise(96, 96, 1);
  for (size_t i = 0; i < noise.size(); ++i) noise.data()[i] = u(rng);
  RollerOptions o;
  o.width = o.height = 200;
  RollerReport rep;
  auto map = RollerSynthesis(noise, noise, o, &rep);
  ASSERT_TRUE(map.ok()) << map.status().message();
  EXPECT_TRUE(rep.frequency_fallback);
  EXPECT_NE(rep.fallback_reason.find("no dominant low frequency"), std::string::npos) << rep.fallback_reason;
  EXPECT_EQ(rep.frequency_rows, o.fallback_frequency);
  EXPECT_TRUE(ValidateMap(*map).ok());
}

TEST(Roller, PeriodicStripesGiveTheirPeriod) {
  Image stripes(128, 128, 1);
  for (int y = 0; y < 128; ++y)
    for (int x = 0; x < 128; ++x) stripes.at(x, y) = float(0.5 + 0.5 * std::sin(2 * M_PI * x / 16.0) * std::cos(2 * M_PI * y / 32.0));
  double rows = 0, columns = 0;
  std::string why;
  ASSERT_TRUE(DominantFrequencies(stripes, &rows, &columns, &why)) << why;
  EXPECT_EQ(columns, 8);  // 128 / 16
  EXPECT_EQ(rows, 4);     // 128 / 32
}

TEST(Roller, RefusesATooSmallSample) {
  Image tiny(4, 4, 1, 0.5f);
  RollerOptions o;
  EXPECT_FALSE(RollerSynthesis(tiny, tiny, o, nullptr).ok());
}

}  // namespace
}  // namespace mesocap
