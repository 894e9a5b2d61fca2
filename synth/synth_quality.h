// How good a synthesis is, measured from the map and the images it makes: the colour step across
// every cut against the sample's own neighbour step (seams), and the steerable-pyramid subband
// histograms against the sample's (statistics). The baseline both are judged against: patches of
// the same size placed at random offsets.
#pragma once

#include <cstdint>
#include <vector>

#include "core/image.h"
#include "synth/synth_map.h"

namespace mesocap {

struct SeamMeasure {
  double mean_cut_step = 0;     // mean L2 step between neighbours whose sources are not neighbours
  long cut_pairs = 0;
  // The sample's mean L2 step between 4-neighbours in the same directions as the cut pairs
  // (horizontal and vertical steps weighted by how many cut pairs run each way).
  double mean_sample_step = 0;
  double ratio() const { return mean_sample_step > 0 ? mean_cut_step / mean_sample_step : 0; }
};

// `output` is the map applied to `sample` (same channels). With `wrap`, the pairs across the
// right/left and bottom/top edges count too (a tile repeated next to itself).
SeamMeasure MeasureSeams(const SynthMap& map, const Image& output, const Image& sample, bool wrap = false);

// Patches of `patch` x `patch` texels, each from a uniformly random offset of the sample.
SynthMap RandomTilingMap(int sample_width, int sample_height, int width, int height, int patch, uint32_t seed);

// Mean 1-D Wasserstein distance between the histograms of `a`'s and `b`'s Laplacian bands (a
// Gaussian stack's differences, spacing 1, 2, 4, ... while both images span 8 of them) and of their
// derivatives along four orientations (0, 45, 90, 135 deg, central differences), over bands and
// channels: a second, simpler view of the local statistics than the steerable pyramid's.
double LaplacianGradientDistance(const Image& a, const Image& b);

// How a map uses its sample (docs: the synthesis issue's "no streaks" and "per-texel" rules):
struct MapUsage {
  // Output texels whose source texel (floor of the map's coordinates) is that of their left or
  // upper neighbour: one sample texel stretched across the output.
  double repeat_share = 0;
  double used_share = 0;           // distinct sample texels used / sample texels
  long largest_coherent_region = 0;  // texels of the largest 4-connected region continuing one source offset
};
MapUsage MeasureMapUsage(const SynthMap& map);

// Per output texel, the id (0, 1, ... in row-major order of first appearance) of its coherent
// region: 4-connected texels each of which continues its left or upper neighbour's source, stepped
// in that neighbour's orientation (the seam measure's continuation). Texton synthesis's patch ids.
std::vector<int32_t> CoherentRegions(const SynthMap& map);

// Mean 1-D Wasserstein distance between the subband histograms (steerable pyramid, 4
// orientations, the scales both images have) of `a` and `b`, over bands and channels.
double SubbandDistance(const Image& a, const Image& b);

}  // namespace mesocap
