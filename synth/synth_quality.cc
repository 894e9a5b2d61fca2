#include "synth/synth_quality.h"

#include <algorithm>
#include <cmath>
#include <random>

#include "reconstruct/slice_statistics.h"
#include "synth/feature_distance.h"

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

}  // namespace mesocap
