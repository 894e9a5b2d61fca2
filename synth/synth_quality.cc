#include "synth/synth_quality.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <unordered_set>

#include "reconstruct/quantiles.h"
#include "reconstruct/slice_statistics.h"
#include "synth/feature_distance.h"
#include "synth/separable_filter.h"

namespace mesocap {

namespace {

// True when output texel q continues the source of p (q's source is p's source stepped by the
// same offset in p's patch orientation).
bool Continues(const SynthMap& map, int px, int py, int qx, int qy, int dx, int dy) {
  const size_t p = map.index(px, py);
  const Eigen::Vector2d step = RotatedStep(dx, dy, map.rotation_deg[p]);
  const int ex = int(std::floor(map.source_x[p] + step.x())), ey = int(std::floor(map.source_y[p] + step.y()));
  const Eigen::Vector2i q = map.SourceTexel(qx, qy);
  return q.x() == ex && q.y() == ey;
}

}  // namespace

SeamMeasure MeasureSeams(const SynthMap& map, const Image& output, const Image& sample, bool wrap) {
  // The sample's own steps per direction: a cut between horizontal neighbours is compared with
  // the sample's horizontal steps (anisotropic materials differ a lot between the two).
  const int C = output.channels();
  double sample_step[2] = {0, 0};
  long sample_pairs[2] = {0, 0};
  for (int y = 0; y < sample.height(); ++y)
    for (int x = 0; x < sample.width(); ++x) {
      if (x + 1 < sample.width()) sample_step[0] += FeatureDistance(sample.pixel(x, y), sample.pixel(x + 1, y), C), ++sample_pairs[0];
      if (y + 1 < sample.height()) sample_step[1] += FeatureDistance(sample.pixel(x, y), sample.pixel(x, y + 1), C), ++sample_pairs[1];
    }
  for (int d = 0; d < 2; ++d) sample_step[d] = sample_pairs[d] ? sample_step[d] / sample_pairs[d] : 0;

  SeamMeasure m;
  double sum = 0, expected = 0;
  const int W = map.width, H = map.height;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x)
      for (int d = 0; d < 2; ++d) {
        const int dx = d == 0, dy = d == 1;
        int qx = x + dx, qy = y + dy;
        if (qx >= W || qy >= H) {
          if (!wrap) continue;
          qx %= W, qy %= H;
        }
        if (Continues(map, x, y, qx, qy, dx, dy)) continue;
        sum += FeatureDistance(output.pixel(x, y), output.pixel(qx, qy), C);
        expected += sample_step[d];
        ++m.cut_pairs;
      }
  m.mean_cut_step = m.cut_pairs ? sum / m.cut_pairs : 0;
  m.mean_sample_step = m.cut_pairs ? expected / m.cut_pairs : 0.5 * (sample_step[0] + sample_step[1]);
  return m;
}

SynthMap RandomTilingMap(int sample_width, int sample_height, int width, int height, int patch, uint32_t seed) {
  SynthMap map(width, height, sample_width, sample_height, "random-tiling");
  std::mt19937 rng(seed);
  const int px = std::min(patch, sample_width), py = std::min(patch, sample_height);
  const int cells_x = (width + px - 1) / px;
  for (int cy = 0; cy * py < height; ++cy)
    for (int cx = 0; cx < cells_x; ++cx) {
      const int ox = std::uniform_int_distribution<int>(0, sample_width - px)(rng);
      const int oy = std::uniform_int_distribution<int>(0, sample_height - py)(rng);
      for (int y = cy * py; y < std::min(height, (cy + 1) * py); ++y)
        for (int x = cx * px; x < std::min(width, (cx + 1) * px); ++x)
          map.Set(x, y, ox + (x - cx * px) + 0.5f, oy + (y - cy * py) + 0.5f, 0, cy * cells_x + cx);
    }
  return map;
}

double SubbandDistance(const Image& a, const Image& b) {
  SliceStatisticsOptions options;
  options.pyramid.levels = std::min(MaxPyramidLevels(a.width(), a.height()), MaxPyramidLevels(b.width(), b.height()));
  const SliceStatistics sa = ComputeSliceStatistics(a, options), sb = ComputeSliceStatistics(b, options);
  double sum = 0;
  int count = 0;
  for (int c = 0; c < std::min(sa.channels, sb.channels); ++c)
    for (int k = 0; k < sa.band_count; ++k, ++count) sum += WassersteinDistance(sa.band(c, k), sb.band(c, k));
  return count ? sum / count : 0;
}

namespace {

// The bands of one channel: Laplacian stack levels, then the four oriented derivatives.
std::vector<std::vector<float>> LaplacianGradientBands(const Image& image, int c, int levels) {
  static const std::vector<float> kBinomial = {1 / 16.f, 4 / 16.f, 6 / 16.f, 4 / 16.f, 1 / 16.f};
  const int w = image.width(), h = image.height();
  Image level(w, h, 1);
  for (size_t i = 0; i < level.pixel_count(); ++i) level.data()[i] = image.data()[i * image.channels() + c];
  std::vector<std::vector<float>> bands;
  std::vector<float> oriented[4];
  for (auto& o : oriented) o.reserve(level.pixel_count());
  for (int y = 1; y + 1 < h; ++y)
    for (int x = 1; x + 1 < w; ++x) {
      auto at = [&](int dx, int dy) { return level.at(x + dx, y + dy); };
      oriented[0].push_back(0.5f * (at(1, 0) - at(-1, 0)));
      oriented[1].push_back(0.3535534f * (at(1, 1) - at(-1, -1)));
      oriented[2].push_back(0.5f * (at(0, 1) - at(0, -1)));
      oriented[3].push_back(0.3535534f * (at(-1, 1) - at(1, -1)));
    }
  for (int l = 0, step = 1; l < levels; ++l, step *= 2) {  // an a-trous Laplacian stack
    Image blurred = SeparableFilter(level, kBinomial, step, 1);
    std::vector<float> band(level.pixel_count());
    for (size_t i = 0; i < band.size(); ++i) band[i] = level.data()[i] - blurred.data()[i];
    bands.push_back(std::move(band));
    level = std::move(blurred);
  }
  for (auto& o : oriented) bands.push_back(std::move(o));
  return bands;
}

}  // namespace

double LaplacianGradientDistance(const Image& a, const Image& b) {
  int levels = 0;
  for (int span = 8; span <= std::min({a.width(), a.height(), b.width(), b.height()}); span *= 2) ++levels;
  double sum = 0;
  int count = 0;
  for (int c = 0; c < std::min(a.channels(), b.channels()); ++c) {
    const auto ba = LaplacianGradientBands(a, c, levels), bb = LaplacianGradientBands(b, c, levels);
    for (size_t k = 0; k < ba.size(); ++k, ++count)
      sum += WassersteinDistance(InverseCdfOf(ba[k]), InverseCdfOf(bb[k]));
  }
  return count ? sum / count : 0;
}

MapUsage MeasureMapUsage(const SynthMap& map) {
  MapUsage u;
  const int W = map.width, H = map.height;
  if (W == 0 || H == 0) return u;
  std::vector<int32_t> source(size_t(W) * H);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const Eigen::Vector2i s = map.SourceTexel(x, y);
      source[map.index(x, y)] = s.y() * map.sample_width + s.x();
    }
  long repeats = 0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const int32_t s = source[map.index(x, y)];
      repeats += (x > 0 && source[map.index(x - 1, y)] == s) || (y > 0 && source[map.index(x, y - 1)] == s);
    }
  u.repeat_share = double(repeats) / (double(W) * H);
  u.used_share = double(std::unordered_set<int32_t>(source.begin(), source.end()).size()) /
                 (double(map.sample_width) * map.sample_height);
  const std::vector<int32_t> region = CoherentRegions(map);
  std::vector<long> size(region.size(), 0);
  for (int32_t r : region) u.largest_coherent_region = std::max(u.largest_coherent_region, ++size[r]);
  return u;
}

std::vector<int32_t> CoherentRegions(const SynthMap& map) {
  const int W = map.width, H = map.height;
  std::vector<int32_t> root(size_t(W) * H);
  std::iota(root.begin(), root.end(), 0);
  auto find = [&](int32_t i) {
    while (root[i] != i) i = root[i] = root[root[i]];
    return i;
  };
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x)
      for (int d = 0; d < 2; ++d) {
        const int qx = x + (d == 0), qy = y + (d == 1);
        if (qx >= W || qy >= H || !Continues(map, x, y, qx, qy, d == 0, d == 1)) continue;
        root[find(int32_t(map.index(qx, qy)))] = find(int32_t(map.index(x, y)));
      }
  std::vector<int32_t> id(root.size(), -1), region(root.size());
  int32_t next = 0;
  for (size_t i = 0; i < root.size(); ++i) {
    const int32_t r = find(int32_t(i));
    if (id[r] < 0) id[r] = next++;
    region[i] = id[r];
  }
  return region;
}

}  // namespace mesocap
