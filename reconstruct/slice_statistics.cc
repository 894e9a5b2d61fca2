#include "reconstruct/slice_statistics.h"

#include <fftw3.h>

#include <algorithm>
#include <cmath>
#include <complex>

#include "core/fftw_buffers.h"
#include "core/status.h"

namespace mesocap {

bool SliceStatisticsOptions::Check() const { return pyramid.Check() && quantiles >= 2; }

std::vector<float> ChannelPlane(const Image& image, int channel) {
  std::vector<float> plane(image.pixel_count());
  const float* src = image.data() + channel;
  const int stride = image.channels();
  for (size_t i = 0; i < plane.size(); ++i) plane[i] = src[i * stride];
  return plane;
}

void SetChannelPlane(Image* image, int channel, std::span<const float> plane) {
  MESOCAP_CHECK(plane.size() == image->pixel_count(), "plane size");
  float* dst = image->data() + channel;
  const int stride = image->channels();
  for (size_t i = 0; i < plane.size(); ++i) dst[i * stride] = plane[i];
}

SliceStatistics ComputeSliceStatistics(const Image& slice, const SliceStatisticsOptions& options) {
  SliceStatistics stats;
  stats.channels = slice.channels();
  for (int c = 0; c < slice.channels(); ++c) {
    const std::vector<float> plane = ChannelPlane(slice, c);
    stats.pixels.push_back(InverseCdfOf(plane, options.quantiles));
    const SteerablePyramid pyramid = BuildSteerablePyramid(plane.data(), slice.width(), slice.height(), options.pyramid);
    stats.band_count = pyramid.band_count();
    for (const PyramidBand& band : pyramid.bands) stats.bands.push_back(InverseCdfOf(band.values, options.quantiles));
  }
  return stats;
}

Image NoiseDifference(const Image& a, const Image& b) {
  MESOCAP_CHECK(a.width() == b.width() && a.height() == b.height() && a.channels() == b.channels(),
                "noise difference of slices of different sizes");
  Image diff(a.width(), a.height(), a.channels());
  const float inv_sqrt2 = float(1 / std::sqrt(2.0));
  for (size_t i = 0; i < a.pixel_count() * size_t(a.channels()); ++i) diff.data()[i] = (a.data()[i] - b.data()[i]) * inv_sqrt2;
  return diff;
}

namespace {

double Variance(const InverseCdf& q) {
  double mean = 0, square = 0;
  for (float v : q.values) mean += v, square += double(v) * v;
  mean /= double(q.values.size());
  return std::max(0.0, square / double(q.values.size()) - mean * mean);
}

void ShrinkBy(InverseCdf* q, const InverseCdf& noise) {
  const double variance = Variance(*q);
  if (!(variance > 0) || noise.empty()) return;
  const double factor = std::sqrt(std::max(0.05, 1.0 - Variance(noise) / variance));
  const double mean = q->Mean();
  for (float& v : q->values) v = float(mean + (v - mean) * factor);
}

}  // namespace

void RemoveNoiseVariance(SliceStatistics* measured, const SliceStatistics& noise, int first_channel) {
  MESOCAP_CHECK(noise.channels == measured->channels && noise.band_count == measured->band_count,
                "noise statistics of a different pyramid");
  for (int c = std::max(0, first_channel); c < measured->channels; ++c) {
    ShrinkBy(&measured->pixels[size_t(c)], noise.pixels[size_t(c)]);
    for (int b = 0; b < measured->band_count; ++b)
      ShrinkBy(&measured->bands[size_t(c) * measured->band_count + b], noise.band(c, b));
  }
}

SliceStatistics BlendSliceStatistics(std::span<const SliceStatistics* const> stats, std::span<const double> weights) {
  MESOCAP_CHECK(!stats.empty(), "no statistics to blend");
  return BlendSliceStatistics(stats, std::vector<std::vector<double>>(stats[0]->channels, {weights.begin(), weights.end()}));
}

SliceStatistics BlendSliceStatistics(std::span<const SliceStatistics* const> stats,
                                     const std::vector<std::vector<double>>& weights_by_channel,
                                     std::span<const BandMap* const> maps) {
  MESOCAP_CHECK(!stats.empty() && int(weights_by_channel.size()) == stats[0]->channels, "one weight list per channel");
  MESOCAP_CHECK(maps.empty() || maps.size() == stats.size(), "one band map per statistics");
  SliceStatistics out;
  out.channels = stats[0]->channels;
  out.band_count = stats[0]->band_count;
  for (const auto& weights : weights_by_channel) MESOCAP_CHECK(weights.size() == stats.size(), "one weight per statistics");
  for (size_t s = 0; s < stats.size(); ++s) {
    MESOCAP_CHECK(stats[s]->channels == out.channels && stats[s]->band_count == out.band_count,
                  "statistics of slices with different sizes or channels");
    const BandMap* map = maps.empty() ? nullptr : maps[s];
    MESOCAP_CHECK(!map || (int(map->from.size()) == out.band_count && map->negated.size() == map->from.size()),
                  "a band map of another band count");
  }
  std::vector<const InverseCdf*> column(stats.size());
  std::vector<char> negated(maps.empty() ? 0 : stats.size(), 0);
  out.pixels.reserve(size_t(out.channels));
  for (int c = 0; c < out.channels; ++c) {
    for (size_t s = 0; s < stats.size(); ++s) column[s] = &stats[s]->pixels[size_t(c)];
    out.pixels.push_back(BlendInverseCdfs(column, weights_by_channel[size_t(c)]));
  }
  out.bands.reserve(size_t(out.channels) * size_t(out.band_count));
  for (int c = 0; c < out.channels; ++c)
    for (int b = 0; b < out.band_count; ++b) {
      for (size_t s = 0; s < stats.size(); ++s) {
        const BandMap* map = maps.empty() ? nullptr : maps[s];
        column[s] = &stats[s]->band(c, map ? map->from[size_t(b)] : b);
        if (map) negated[s] = map->negated[size_t(b)];
      }
      out.bands.push_back(BlendInverseCdfs(column, weights_by_channel[size_t(c)], negated));
    }
  return out;
}

Image MatchSliceStatistics(const Image& base, const SliceStatistics& target, const SliceStatisticsOptions& options) {
  MESOCAP_CHECK(base.channels() == target.channels, "channel count of base and target statistics");
  Image out(base.width(), base.height(), base.channels());
  for (int c = 0; c < base.channels(); ++c) {
    const std::vector<float> plane = ChannelPlane(base, c);
    SteerablePyramid pyramid = BuildSteerablePyramid(plane.data(), base.width(), base.height(), options.pyramid);
    MESOCAP_CHECK(pyramid.band_count() == target.band_count, "pyramid of the base differs from the statistics'");
    for (int b = 0; b < pyramid.band_count(); ++b) MatchToInverseCdf(pyramid.bands[b].values, target.band(c, b));
    std::vector<float> matched = CollapseSteerablePyramid(pyramid);
    MatchToInverseCdf(matched, target.pixels[c]);
    SetChannelPlane(&out, c, matched);
  }
  return out;
}

void UndoGaussianBlur(Image* image, double sigma, int first_channel, double max_gain) {
  const int w = image->width(), h = image->height(), half = w / 2 + 1, channels = image->channels();
  if (!(sigma > 0) || first_channel >= channels || w == 0 || h == 0) return;
  FftFloatBuffer plane(size_t(w) * size_t(h));
  FftComplexBuffer spectrum(size_t(half) * size_t(h));
  const RealFftPlans& plans = RealFftPlansFor(w, h);
  // The gain per frequency bin, with FFTW's unnormalised round trip folded in.
  std::vector<float> gain(spectrum.n);
  const double k = 2 * M_PI * M_PI * sigma * sigma;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < half; ++x) {
      const double fy = (y <= h / 2 ? y : y - h) / double(h), fx = x / double(w);
      gain[size_t(y) * size_t(half) + size_t(x)] =
          float(std::min(max_gain, std::exp(k * (fx * fx + fy * fy))) / (double(w) * double(h)));
    }
  const size_t texels = size_t(w) * size_t(h);
  for (int c = first_channel; c < channels; ++c) {
    for (size_t i = 0; i < texels; ++i) plane.data[i] = image->data()[i * size_t(channels) + size_t(c)];
    fftwf_execute_dft_r2c(plans.forward, plane.data, spectrum.fftw());
    for (size_t i = 0; i < spectrum.n; ++i) spectrum.data[i] *= gain[i];
    fftwf_execute_dft_c2r(plans.inverse, spectrum.fftw(), plane.data);
    for (size_t i = 0; i < texels; ++i) image->data()[i * size_t(channels) + size_t(c)] = plane.data[i];
  }
}

}  // namespace mesocap
