// Shared by the synthesis tests: virtual-rig BTF exemplars rendered once per test binary.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "synth/exemplar.h"
#include "synth/synth_map.h"

namespace mesocap::testing {

// True BTF slices of `material` at `size` texels for a few (light, view) pairs (several lights,
// two views), written once under the temp dir and loaded as an exemplar.
Exemplar VirtualRigExemplar(const std::string& material, int size = 128);
// The same pairs, for tests that render the truth themselves.
std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> ExemplarPairs();

// A size x size crop (top left) of tests/data/textures/NAME.png, linear RGB.
Image PhotoCrop(const std::string& name, int size);

// The synthesis issue's one baseline for every method on photographs: random-offset tiling of
// 24 x 24 patches of `image` into `width` x `height`, at `seed`; and its subband distance to `image`.
Image RandomTiling(const Image& image, int width, int height, uint32_t seed);
double RandomTilingSubband(const Image& image, int width, int height, uint32_t seed);

// Uniform noise in [0, 1), `channels` per texel, from `seed`.
Image NoiseImage(int width, int height, int channels, uint32_t seed);

// A PTM (RGB) fitted to `material`'s head-on true BTF under 16 lights at 30 and 55 deg, `size`
// texels a side.
Ptm VirtualRigPtm(const std::string& material, int size = 96);
// A PTM (RGB) of a photograph as albedo over its luminance as a height field (`relief` texels per
// unit of luminance), Lambertian under the same 16 lights: a PTM with a photograph's structure.
Ptm PhotoReliefPtm(const Image& photo, double relief = 4);
// The PTM relit head-on, at 40 deg and at 60 deg: the images its syntheses are judged on.
std::vector<Image> RelitUnderThreeLights(const Ptm& ptm);

// Over three seeds from `seed`: every seam ratio (synth_quality.h) of the map applied to each image
// at most `max_seam_ratio` and below 0.8 x random placement's (patches of `block` texels); per
// image, the subband distance to the sample summed over the seeds below random tiling's (one
// seed's comparison swings by a few percent either way with where the first patches land), times
// `statistics_slack` where a method is known to fall short (said where it is used).
void ExpectGoodSeamsAndStatistics(const std::function<SynthMap(uint32_t)>& synthesize, const std::vector<Image>& images,
                                  int block, uint32_t seed, double max_seam_ratio = 1.2, double statistics_slack = 1.0);

}  // namespace mesocap::testing
