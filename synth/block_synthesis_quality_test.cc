// Block synthesis judged by what it makes: seams against the sample's own steps and random
// placement, subband statistics against random tiling, on three virtual-rig BTFs, a PTM fitted to
// one and a plain image. (Minutes under AddressSanitizer: scripts/sanitize.sh leaves it out; the
// search and map tests in block_synthesis_test run there.)
#include <gtest/gtest.h>

#include <functional>

#include "capture/btf_render.h"
#include "capture/rig_material.h"
#include "core/directions.h"
#include "reconstruct/ptm.h"
#include "reconstruct/ptm_legendre.h"
#include "synth/block_synthesis.h"
#include "synth/synth_quality.h"
#include "synth/synth_test_support.h"
#include "tests/testing.h"

namespace mesocap {
namespace {

// Seams no worse than 1.2 x the sample's own steps and well below random placement, and subband
// statistics closer to the sample than random tiling, under every light and view of the exemplar.
struct SeamCase {
  std::string material;
  int block, overlap;    // 0: the defaults (30, block / 6)
  double max_seam_ratio;  // the issue asks 1.2 (stones reached 1.21-1.24 before the seam limit, now 1.13)
};
class BlockSynthesisOnMaterial : public ::testing::TestWithParam<SeamCase> {};

// The map of `options` at `seed`, or a failed test.
std::function<SynthMap(uint32_t)> Synthesizer(const Image& features, BlockSynthesisOptions options) {
  return [&features, options](uint32_t seed) mutable {
    options.seed = seed;
    auto map = BlockSynthesis(features, options, nullptr);
    EXPECT_TRUE(map.ok()) << map.status().message();
    return map.ok() ? *map : SynthMap();
  };
}

TEST_P(BlockSynthesisOnMaterial, BtfSeamsAndStatistics) {
  const Exemplar e = testing::VirtualRigExemplar(GetParam().material);
  const SeamCase& c = GetParam();
  BlockSynthesisOptions o;
  o.width = o.height = 256;
  if (c.block) o.block = c.block, o.overlap = c.overlap;
  std::vector<Image> slices;
  for (int k = 0; k < int(e.slices.size()); ++k) slices.push_back(*e.ReadSlice(k));
  testing::ExpectGoodSeamsAndStatistics(Synthesizer(e.features, o), slices, o.block, testing::SeedFromTestName(), c.max_seam_ratio);
}

INSTANTIATE_TEST_SUITE_P(Materials, BlockSynthesisOnMaterial,
                         ::testing::Values(SeamCase{"weave", 0, 0, 1.2}, SeamCase{"corduroy", 0, 0, 1.2},
                                           SeamCase{"stones", 20, 6, 1.2}),
                         [](const auto& info) { return info.param.material; });

// A PTM of a virtual-rig material, synthesized in the Legendre basis: seams and statistics of the
// relit output under three lights.
TEST(BlockSynthesis, PtmOfAVirtualRigMaterial) {
  const Ptm ptm = testing::VirtualRigPtm("stones");
  BlockSynthesisOptions o;
  o.width = o.height = 200;
  o.block = 24;
  const Image legendre = PtmLegendreCoefficients(ptm);
  testing::ExpectGoodSeamsAndStatistics(Synthesizer(legendre, o), testing::RelitUnderThreeLights(ptm), o.block,
                                        testing::SeedFromTestName());
}

// A plain colour image: its colours are the features.
TEST(BlockSynthesis, PlainImage) {
  const Exemplar e = testing::VirtualRigExemplar("corduroy");
  const Image image = *e.ReadSlice(2);
  BlockSynthesisOptions o;
  o.width = o.height = 256;
  testing::ExpectGoodSeamsAndStatistics(Synthesizer(image, o), {image}, o.block, testing::SeedFromTestName());
}

}  // namespace
}  // namespace mesocap
