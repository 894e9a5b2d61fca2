// Block synthesis of PTMs rendered from real photographs (tests/data/textures; each 96 x 96 crop as
// albedo over its luminance as a height field, testing::PhotoReliefPtm), enlarged to 256 x 256 in
// the Legendre basis and judged relit head-on and at (40, 60) deg, as the synthesis issue measures
// them: seams within 1.2x the sample's own step and subband statistics no worse than random tiling
// of 24 x 24 patches, the mean of three seeds, under each light. With the defaults before (a block
// drawn at random among those within 0.1 of the best, Efros & Freeman) five of the six failed:
// reptile's seams 1.25, bark 1.08-1.09x random tiling's statistics, woodgrain 2.7-3.0x, grass 1.28x,
// rock 2.3-2.4x (brick passed, 0.91-0.96x); the least used admitted block whose cuts meet the seam
// limit reaches 0.55-0.77x with seams 0.80-1.07 (docs/synthesis.md).
#include <gtest/gtest.h>

#include <cstdio>

#include "core/directions.h"
#include "reconstruct/ptm.h"
#include "reconstruct/ptm_legendre.h"
#include "synth/block_synthesis.h"
#include "synth/map_apply.h"
#include "synth/synth_quality.h"
#include "synth/synth_test_support.h"
#include "tests/testing.h"

namespace mesocap {
namespace {

constexpr int kCrop = 96, kOutput = 256, kSeeds = 3;

class BlockOnPhotographPtms : public ::testing::TestWithParam<std::string> {};

TEST_P(BlockOnPhotographPtms, SeamsAndStatisticsNoWorseThanRandomTiling) {
  const Ptm ptm = testing::PhotoReliefPtm(testing::PhotoCrop(GetParam(), kCrop));
  const Image features = PtmLegendreCoefficients(ptm);
  const std::vector<Image> images{RelightPtm(ptm, DirectionFromAnglesDeg(0, 0)), RelightPtm(ptm, DirectionFromAnglesDeg(40, 60))};
  std::vector<double> seams(images.size(), 0.0), subband(images.size(), 0.0), random_subband(images.size(), 0.0);
  for (int s = 0; s < kSeeds; ++s) {
    BlockSynthesisOptions o;
    o.width = o.height = kOutput;
    o.seed = testing::SeedFromTestName() + uint32_t(s);
    Image built;
    auto map = BlockSynthesis(features, o, nullptr, nullptr, &built);
    ASSERT_TRUE(map.ok()) << map.status().message();
    ASSERT_TRUE(ValidateMap(*map).ok());
    EXPECT_EQ(ApplyMapToImage(*map, features), built);  // what was assembled is what the map says
    for (size_t k = 0; k < images.size(); ++k) {
      const Image out = ApplyMapToImage(*map, images[k]);
      seams[k] += MeasureSeams(*map, out, images[k]).ratio() / kSeeds;
      subband[k] += SubbandDistance(out, images[k]) / kSeeds;
      random_subband[k] += testing::RandomTilingSubband(images[k], kOutput, kOutput, o.seed) / kSeeds;
    }
  }
  for (size_t k = 0; k < images.size(); ++k) {
    std::printf("%s light %zu: seams %.3f subband/random %.3f\n", GetParam().c_str(), k, seams[k], subband[k] / random_subband[k]);
    EXPECT_LE(seams[k], 1.2) << "light " << k;
    EXPECT_LE(subband[k], random_subband[k]) << "light " << k << ": subband distance " << subband[k] << " against random tiling's "
                                             << random_subband[k];
  }
}

INSTANTIATE_TEST_SUITE_P(Corpus, BlockOnPhotographPtms,
                         ::testing::Values("brick", "reptile", "bark", "woodgrain", "grass", "rock"),
                         [](const auto& info) { return info.param; });

}  // namespace
}  // namespace mesocap
