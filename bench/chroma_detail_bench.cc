// The cost calibrate pays per JPEG shot (3000x2000) to restore its colour detail
// (core/chroma_detail.h), next to the plain linearisation it replaces; wall time on all cores.
//   build/bench/bench_chroma_detail
#include <benchmark/benchmark.h>

#include <cmath>

#include "core/chroma_detail.h"

namespace mesocap {
namespace {

const ImageU8& Shot() {
  static const ImageU8 shot = [] {
    ImageU8 srgb(3000, 2000, 3);
    for (int y = 0; y < srgb.height(); ++y)
      for (int x = 0; x < srgb.width(); ++x)
        for (int c = 0; c < 3; ++c) srgb.at(x, y, c) = uint8_t(128 + 100 * std::sin(0.9 * x + 0.7 * y + c) * std::cos(0.05 * y));
    return srgb;
  }();
  return shot;
}

void BM_PlainLinear(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(LinearWithChromaDetail(Shot(), {1, 1}));
}
void BM_ChromaDetail420(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(LinearWithChromaDetail(Shot(), {2, 2}));
}
BENCHMARK(BM_PlainLinear)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_ChromaDetail420)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace mesocap
