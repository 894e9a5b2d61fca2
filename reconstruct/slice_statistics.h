// The alignment-insensitive statistics Ngan & Durand keep of every measured BTF slice (section
// 3.1): per colour channel, the pixel histogram and the histogram of every steerable-pyramid
// subband (4 orientations, all scales), each stored as an inverse CDF so that statistics of
// neighbouring directions can be blended and extrapolated (section 3.2).
#pragma once

#include <span>
#include <vector>

#include "core/image.h"
#include "reconstruct/quantiles.h"
#include "reconstruct/steerable_pyramid.h"

namespace mesocap {

struct SliceStatisticsOptions {
  SteerablePyramidOptions pyramid;
  int quantiles = kDefaultQuantiles;
  bool Check() const;
};

struct SliceStatistics {
  int channels = 0;
  int band_count = 0;                // pyramid bands per channel (high-pass .. low-pass)
  std::vector<InverseCdf> pixels;    // [channel]
  std::vector<InverseCdf> bands;     // [channel * band_count + band]

  const InverseCdf& band(int channel, int b) const { return bands[size_t(channel) * band_count + b]; }
  bool empty() const { return pixels.empty(); }
};

// Statistics of one slice (any size the pyramid accepts).
SliceStatistics ComputeSliceStatistics(const Image& slice, const SliceStatisticsOptions& options = {});

// A measured slice's noise widens its histograms, and blending histograms (unlike blending
// pixels) keeps that width: statistics of noisy slices make a reconstruction noisier, and more
// colourful where the material's colour barely varies. Two slices of one view at nearby lights
// share their signal but not their noise, so (a - b) / sqrt(2) (per texel, same size) is an image
// of one slice's noise.
Image NoiseDifference(const Image& a, const Image& b);
// Takes the variance of `noise` (statistics of a noise image, same pyramid) out of `measured`'s
// channels [first_channel, channels): every pixel and subband inverse CDF is shrunk about its
// mean by sqrt(1 - var_noise / var), at least by sqrt(0.05).
void RemoveNoiseVariance(SliceStatistics* measured, const SliceStatistics& noise, int first_channel);

// The capture chain blurs a measured slice (the camera's pixels and optics, the resampling's
// reads): undoes a Gaussian blur of `sigma` texels on channels [first_channel, channels) by its
// inverse in the Fourier domain (periodic), exp(2 pi^2 sigma^2 |f|^2), the gain capped at
// `max_gain` so the finest frequencies' noise is not blown up.
void UndoGaussianBlur(Image* image, double sigma, int first_channel, double max_gain = 3.0);

// Statistics read through a map of their bands (a mirror image of the texture: ImagedBands):
// band b of each channel is the source's band from[b], negated (the distribution of -x) where
// negated[b]; the pixel histograms are the source's.
struct BandMap {
  std::vector<int> from;
  std::vector<char> negated;
};

// Inverse-CDF blend of compatible statistics; weights sum to one and may be negative.
SliceStatistics BlendSliceStatistics(std::span<const SliceStatistics* const> stats, std::span<const double> weights);
// The same with weights per channel: `weights_by_channel[c]` blends channel c. `maps`, empty or
// one per statistics: stats[s] is read through maps[s] (null: as it is), without a copy.
SliceStatistics BlendSliceStatistics(std::span<const SliceStatistics* const> stats,
                                     const std::vector<std::vector<double>>& weights_by_channel,
                                     std::span<const BandMap* const> maps = {});

// The transfer of section 3.2: decompose `base`, match every subband to `target`'s, collapse,
// then match the pixel histogram. `base` and the slices `target` was measured on must share a
// size (pyramid bands must correspond).
Image MatchSliceStatistics(const Image& base, const SliceStatistics& target, const SliceStatisticsOptions& options = {});

// The channel planes of an interleaved image, and back.
std::vector<float> ChannelPlane(const Image& image, int channel);
void SetChannelPlane(Image* image, int channel, std::span<const float> plane);

}  // namespace mesocap
