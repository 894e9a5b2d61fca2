#include "synth/block_synthesis.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "synth/graphcut_fit.h"
#include "synth/synth_quality.h"
#include "synth/synth_test_support.h"
#include "tests/testing.h"

namespace mesocap {
namespace {

// An output-size image to query with, as a synthesis in progress looks: pieces of the sample (in
// 16 x 16 tiles from random offsets) with a little noise, so neighbourhoods resemble the sample's
// without being copies of it.
Image QueryCanvas(const Image& sample, int width, int height, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> sx(0, sample.width() - 1), sy(0, sample.height() - 1);
  std::normal_distribution<float> noise(0, 0.002f);
  Image canvas(width, height, sample.channels());
  for (int ty = 0; ty < height; ty += 16)
    for (int tx = 0; tx < width; tx += 16) {
      const int ox = sx(rng), oy = sy(rng);
      for (int y = ty; y < std::min(height, ty + 16); ++y)
        for (int x = tx; x < std::min(width, tx + 16); ++x)
          for (int f = 0; f < sample.channels(); ++f)
            canvas.at(x, y, f) = sample.at((x - tx + ox) % sample.width(), (y - ty + oy) % sample.height(), f) + noise(rng);
    }
  return canvas;
}

// On every query of a test set (all three neighbourhood shapes, with and without tolerance) the
// rejection search returns exactly the brute-force candidates and distances, and rejects most
// candidates on their bound alone.
TEST(BlockSynthesis, RejectionSearchReturnsExactlyTheBruteForceBest) {
  for (const auto& [material, basis] : {std::pair{"stones", BlockBasis::kPrincipal}, {"weave", BlockBasis::kPrincipal},
                                        {"stones", BlockBasis::kWalshHadamard}}) {
    const Exemplar e = testing::VirtualRigExemplar(material, 64);
    const BlockSearcher searcher(e.features, 16, 4, 8, -1, basis);
    const Image canvas = QueryCanvas(e.features, 60, 60, testing::SeedFromTestName());
    long rejected = 0, candidates = 0;
    for (int y0 : {0, 12, 36})
      for (int x0 : {0, 12, 40}) {
        if (x0 == 0 && y0 == 0) continue;
        for (double tolerance : {0.0, 0.1}) {
          const BlockSearchResult fast = searcher.Search(canvas, x0, y0, tolerance, BlockSearch::kRejection);
          const BlockSearchResult brute = searcher.Search(canvas, x0, y0, tolerance, BlockSearch::kBruteForce);
          ASSERT_FALSE(brute.candidates.empty());
          ASSERT_EQ(fast.candidates.size(), brute.candidates.size()) << material << " at " << x0 << "," << y0;
          for (size_t i = 0; i < brute.candidates.size(); ++i) {
            EXPECT_EQ(fast.candidates[i].index, brute.candidates[i].index);
            EXPECT_EQ(fast.candidates[i].distance, brute.candidates[i].distance);
          }
          EXPECT_EQ(fast.rejected + fast.full_distances, searcher.candidate_count());
          rejected += fast.rejected, candidates += searcher.candidate_count();
        }
      }
    const double fraction = double(rejected) / double(candidates);
    std::printf("%s, %s basis: %.1f%% of candidates rejected on their bound\n", material,
                basis == BlockBasis::kPrincipal ? "principal" : "Walsh-Hadamard", 100 * fraction);
    if (basis == BlockBasis::kPrincipal) {
      EXPECT_GT(fraction, 0.5) << material;
    }
  }
}

// Excluded candidates take no part in either search, and both still agree exactly.
TEST(BlockSynthesis, ExcludedCandidatesTakeNoPartAndBothSearchesAgree) {
  const Exemplar e = testing::VirtualRigExemplar("stones", 64);
  const BlockSearcher searcher(e.features, 16, 4, 8, -1);
  const Image canvas = QueryCanvas(e.features, 60, 60, testing::SeedFromTestName());
  for (int x0 : {12, 40}) {
    const BlockSearchResult open = searcher.Search(canvas, x0, 12, 0.1, BlockSearch::kBruteForce);
    ASSERT_FALSE(open.candidates.empty());
    const int columns = searcher.candidate_columns();
    const int bx = int(open.candidates[0].index % columns), by = int(open.candidates[0].index / columns);
    const auto near_best = [&](int x, int y) { return std::abs(x - bx) < 3 && std::abs(y - by) < 3; };
    const BlockSearchResult fast = searcher.Search(canvas, x0, 12, 0.1, BlockSearch::kRejection, near_best);
    const BlockSearchResult brute = searcher.Search(canvas, x0, 12, 0.1, BlockSearch::kBruteForce, near_best);
    ASSERT_FALSE(brute.candidates.empty());
    ASSERT_EQ(fast.candidates.size(), brute.candidates.size());
    for (size_t i = 0; i < brute.candidates.size(); ++i) {
      EXPECT_EQ(fast.candidates[i].index, brute.candidates[i].index);
      EXPECT_EQ(fast.candidates[i].distance, brute.candidates[i].distance);
      EXPECT_FALSE(near_best(int(brute.candidates[i].index % columns), int(brute.candidates[i].index / columns)));
    }
  }
}

// Without the continuation rule a block continues its neighbour's source (its overlap matches
// exactly) and coherent regions span several blocks; with it none is larger than one block.
TEST(BlockSynthesis, ContinuationRuleKeepsCoherentRegionsWithinABlock) {
  const Exemplar e = testing::VirtualRigExemplar("stones", 64);
  BlockSynthesisOptions o;
  o.width = o.height = 128;
  o.block = 16;
  o.seed = testing::SeedFromTestName();
  BlockSynthesisReport r;
  o.continuation_exclusion = 0;
  auto free = BlockSynthesis(e.features, o, &r);
  o.continuation_exclusion = o.EffectiveOverlap();
  auto ruled = BlockSynthesis(e.features, o, &r);
  ASSERT_TRUE(free.ok() && ruled.ok());
  EXPECT_GT(MeasureMapUsage(*free).largest_coherent_region, 2 * o.block * o.block);
  EXPECT_LE(MeasureMapUsage(*ruled).largest_coherent_region, o.block * o.block);
}

// The map is valid and reproduces the assembled features bit for bit; brute force makes the same
// map (the same candidates, so the same random draws).
TEST(BlockSynthesis, ValidMapReproducedBitForBitAndBruteForceAgrees) {
  const Exemplar e = testing::VirtualRigExemplar("corduroy", 64);
  BlockSynthesisOptions o;
  o.width = 100, o.height = 77;
  o.block = 16;
  o.seed = testing::SeedFromTestName();
  Image built, built_brute;
  BlockSynthesisReport report, report_brute;
  auto map = BlockSynthesis(e.features, o, &report, nullptr, &built);
  ASSERT_TRUE(map.ok()) << map.status().message();
  EXPECT_TRUE(ValidateMap(*map).ok()) << ValidateMap(*map).message();
  EXPECT_EQ(ApplyMapToImage(*map, e.features), built);
  o.search = BlockSearch::kBruteForce;
  auto brute = BlockSynthesis(e.features, o, &report_brute, nullptr, &built_brute);
  ASSERT_TRUE(brute.ok());
  EXPECT_EQ(map->source_x, brute->source_x);
  EXPECT_EQ(map->source_y, brute->source_y);
  EXPECT_EQ(map->patch, brute->patch);
  EXPECT_EQ(built, built_brute);
  EXPECT_LT(report.full_distances, report_brute.full_distances / 4);
}

// The share of `map`'s texels drawn from the sample's outer band `band` texels wide.
double BorderBandShare(const SynthMap& map, int band) {
  long inside = 0;
  for (size_t i = 0; i < map.source_x.size(); ++i) {
    const int x = int(map.source_x[i]), y = int(map.source_y[i]);
    inside += x >= band && y >= band && x < map.sample_width - band && y < map.sample_height - band;
  }
  return 1.0 - double(inside) / double(map.source_x.size());
}

// A block position drawn at random holds a central texel in `block` times as many positions as a
// border texel, so the output drew on the sample's border band less than on its centre; balancing
// the usage brings the band's share toward its area. On noise (no position matches better than
// another) the outer 8 texels of a 64-texel sample cover 44% of it.
TEST(BlockSynthesis, BalancedUsageDrawsMoreOnTheBorderBand) {
  const Image sample = testing::NoiseImage(64, 64, 3, testing::SeedFromTestName());
  BlockSynthesisOptions o;
  o.width = o.height = 192;
  o.block = 16;
  o.seed = testing::SeedFromTestName();
  const double area = 1.0 - (48.0 * 48.0) / (64.0 * 64.0);
  o.balance_usage = false;
  auto drawn = BlockSynthesis(sample, o, nullptr);
  o.balance_usage = true;
  auto balanced = BlockSynthesis(sample, o, nullptr);
  ASSERT_TRUE(drawn.ok() && balanced.ok());
  const double drawn_share = BorderBandShare(*drawn, 8), balanced_share = BorderBandShare(*balanced, 8);
  std::printf("border band: %.3f of the area, drawn at random %.3f, balanced %.3f\n", area, drawn_share, balanced_share);
  EXPECT_LT(drawn_share, 0.5 * area);
  EXPECT_GT(balanced_share, 0.65 * area);
  EXPECT_GT(MeasureMapUsage(*balanced).used_share, MeasureMapUsage(*drawn).used_share);
}

// With a seam limit each block is the first admitted one (least used first) whose cuts err at most
// the limit x the sample's mean step: the cuts err less than without it, and a limit every cut meets
// changes nothing.
TEST(BlockSynthesis, SeamLimitLowersTheCutsErrorAndAnUnreachedLimitChangesNothing) {
  const Exemplar e = testing::VirtualRigExemplar("stones", 64);
  BlockSynthesisOptions o;
  o.width = o.height = 128;
  o.block = 16;
  o.tolerance = 3;  // many blocks admitted, the least used of them often a poor fit
  o.seed = testing::SeedFromTestName();
  BlockSynthesisReport free, limited, unreached;
  o.seam_limit = 0;
  auto a = BlockSynthesis(e.features, o, &free);
  o.seam_limit = 1;
  auto b = BlockSynthesis(e.features, o, &limited);
  o.seam_limit = 1e9;
  auto c = BlockSynthesis(e.features, o, &unreached);
  ASSERT_TRUE(a.ok() && b.ok() && c.ok());
  std::printf("mean cut error: free %.4f, limit 1: %.4f (sample step %.4f)\n", free.mean_cut_error, limited.mean_cut_error,
              MeanNeighbourStep(e.features));
  EXPECT_LT(limited.mean_cut_error, 0.9 * free.mean_cut_error);
  EXPECT_EQ(a->source_x, c->source_x);
  EXPECT_EQ(a->source_y, c->source_y);
}

TEST(BlockSynthesis, RefusesASampleSmallerThanABlockAndABadOverlap) {
  const Image small(20, 40, 3, 0.5f);
  BlockSynthesisOptions o;
  auto map = BlockSynthesis(small, o, nullptr);
  ASSERT_FALSE(map.ok());
  EXPECT_NE(map.status().message().find("smaller than a block"), std::string::npos) << map.status().message();
  o.block = 8, o.overlap = 8;
  map = BlockSynthesis(small, o, nullptr);
  ASSERT_FALSE(map.ok());
  EXPECT_NE(map.status().message().find("overlap"), std::string::npos) << map.status().message();
}

}  // namespace
}  // namespace mesocap
