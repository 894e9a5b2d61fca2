#include "synth/separable_filter.h"

#include "core/parallel.h"

namespace mesocap {

int MirrorIndex101(int i, int n) {
  if (n == 1) return 0;
  const int period = 2 * (n - 1);
  i %= period;
  if (i < 0) i += period;
  return i < n ? i : period - i;
}

Image SeparableFilter(const Image& image, const std::vector<float>& taps, int step, int num_threads) {
  const int W = image.width(), H = image.height(), C = image.channels(), radius = int(taps.size()) / 2;
  Image across(W, H, C), out(W, H, C);
  ParallelFor(0, H, [&](int y) {
    for (int x = 0; x < W; ++x) {
      float* o = across.pixel(x, y);
      for (int i = -radius; i <= radius; ++i) {
        const float* in = image.pixel(MirrorIndex101(x + i * step, W), y);
        for (int c = 0; c < C; ++c) o[c] += taps[i + radius] * in[c];
      }
    }
  }, num_threads);
  ParallelFor(0, H, [&](int y) {
    float* o = out.row(y);
    for (int i = -radius; i <= radius; ++i) {
      const float* in = across.row(MirrorIndex101(y + i * step, H));
      for (int j = 0; j < W * C; ++j) o[j] += taps[i + radius] * in[j];
    }
  }, num_threads);
  return out;
}

}  // namespace mesocap
