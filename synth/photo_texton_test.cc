// Texton synthesis on real photographs (tests/data/textures: crops of Debian packages' texture
// photographs, see its README), 96 x 96 crops enlarged to 256 x 256, judged on the map as the
// synthesis issue defines it: no streaks (few texels copying their left or upper neighbour's
// source, at least half the sample used), per-texel (no coherent region over a quarter of the
// sample), seams, and the subband statistics against random tiling of 24 x 24 patches.
//
// Seams meet the target (1.2) on all six. Statistics (target 1x random tiling's, measured three
// seeds): brick 0.77, paving 0.74, reptile 0.85, bark 0.96, leaves 0.51, crackle 1.26, which falls
// short and is held to 1.35 (it was 1.03 when the levels stopped at 8 steps of the sample, and
// brick 2.87, bark 2.18, leaves 1.41; README.md's Known limits).
#include <gtest/gtest.h>

#include "synth/exemplar.h"
#include "synth/synth_quality.h"
#include "synth/texton_analysis.h"
#include "synth/texton_synthesis.h"
#include "synth/synth_test_support.h"
#include "tests/testing.h"

namespace mesocap {
namespace {

constexpr int kCrop = 96, kOutput = 256;

Image Crop(const std::string& name) { return testing::PhotoCrop(name, kCrop); }

struct PhotoCase {
  std::string texture;
  double max_seam_ratio;     // target 1.2 (see the file comment)
  double max_subband_ratio;  // against random tiling (target 1; see the file comment)
};

class TextonOnPhotographs : public ::testing::TestWithParam<PhotoCase> {};

// Over three seeds: every map's usage within bounds; seams and statistics as the seeds' mean (one
// seed's swings by several percent either way).
TEST_P(TextonOnPhotographs, NoStreaksPerTexelSeamsAndStatistics) {
  const Image sample = Crop(GetParam().texture);
  const Exemplar e = ImageExemplar(sample);
  auto analysis = AnalyzeTextons(AppearanceImageCount(e), [&](int k) { return AppearanceLuminance(e, k); }, {});
  ASSERT_TRUE(analysis.ok()) << analysis.status().message();
  constexpr int kSeeds = 3;
  double seams = 0, wrap_seams = 0, subband = 0, random_subband = 0;
  for (int s = 0; s < kSeeds; ++s) {
    TextonSynthesisOptions o;
    o.width = o.height = kOutput;
    o.seed = testing::SeedFromTestName() + uint32_t(s);
    auto map = TextonSynthesis(*analysis, o, nullptr);
    ASSERT_TRUE(map.ok()) << map.status().message();
    const MapUsage usage = MeasureMapUsage(*map);
    EXPECT_LE(usage.repeat_share, 0.02) << "texels copying their left or upper neighbour's source, seed " << o.seed;
    EXPECT_GE(usage.used_share, 0.5) << "share of the sample's texels used, seed " << o.seed;
    EXPECT_LE(usage.largest_coherent_region, kCrop * kCrop / 4) << "a block copied whole, seed " << o.seed;
    const Image out = ApplyMapToImage(*map, sample);
    const SeamMeasure inside = MeasureSeams(*map, out, sample), around = MeasureSeams(*map, out, sample, /*wrap=*/true);
    seams += inside.ratio() / kSeeds;
    // The pairs across the right/left and bottom/top edges alone: the output tiles (export marks
    // texton maps REPEAT) when these are as good as the inside's.
    const double wrap_steps = around.mean_cut_step * around.cut_pairs - inside.mean_cut_step * inside.cut_pairs;
    const double wrap_expected = around.mean_sample_step * around.cut_pairs - inside.mean_sample_step * inside.cut_pairs;
    ASSERT_GT(around.cut_pairs, inside.cut_pairs);
    wrap_seams += wrap_steps / wrap_expected / kSeeds;
    subband += SubbandDistance(out, sample) / kSeeds;
    random_subband += testing::RandomTilingSubband(sample, kOutput, kOutput, o.seed) / kSeeds;
  }
  EXPECT_LE(seams, GetParam().max_seam_ratio);
  // 512 pairs per seed cross the edges (130,000 inside), so their mean swings: wrap / inside
  // measured 0.86-1.24 on these six photographs (mean 1.00) with levels down to 8 steps of the
  // sample, 0.77-1.31 (mean 1.01) with levels down to 3 steps, whose larger coherent regions leave
  // fewer cuts on the edges (bound 1.3 before, README's Known limits).
  EXPECT_LE(wrap_seams, 1.4 * seams) << "across the wrap-around edges, against " << seams << " inside";
  EXPECT_LE(subband, GetParam().max_subband_ratio * random_subband) << subband / random_subband << "x random tiling's";
}

// Structured (brick, paving, reptile, crackle), directional (bark) and large-scale (leaves).
INSTANTIATE_TEST_SUITE_P(Corpus, TextonOnPhotographs,
                         ::testing::Values(PhotoCase{"brick", 1.2, 1.0}, PhotoCase{"paving", 1.2, 1.0},
                                           PhotoCase{"reptile", 1.2, 1.0}, PhotoCase{"crackle", 1.2, 1.35},
                                           PhotoCase{"bark", 1.2, 1.1}, PhotoCase{"leaves", 1.2, 0.8}),
                         [](const auto& info) { return info.param.texture; });

}  // namespace
}  // namespace mesocap
