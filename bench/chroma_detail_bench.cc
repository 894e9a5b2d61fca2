// The cost calibrate pays per JPEG shot (3000x2000) to restore its colour detail
// (core/chroma_detail.h), next to the plain linearisation it replaces; wall time on all cores.
// Calibrate restores only the 13 boards' patches (BM_ChromaDetail420RigPatches: their reach in a
// virtual session's shots, 11% of the pixels).
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
void BM_ChromaDetail420RigPatches(benchmark::State& state) {
  // The pixels the 13 patch samplers of a 3000x2000 virtual session read (weave, seed 21, 128 texels).
  const PixelRect patches[] = {{1352, 834, 1608, 1090}, {1851, 850, 2064, 1100}, {1355, 376, 1605, 593},
                               {892, 835, 1110, 1085},  {1353, 1333, 1603, 1547}, {2252, 867, 2377, 1117},
                               {1956, 258, 2172, 523},  {1335, 64, 1586, 189},    {806, 238, 1028, 497},
                               {579, 800, 709, 1052},   {807, 1426, 1025, 1685},  {1362, 1731, 1612, 1863},
                               {1928, 1429, 2150, 1687}};
  for (auto _ : state) benchmark::DoNotOptimize(LinearWithChromaDetail(Shot(), {2, 2}, 64, patches));
}
BENCHMARK(BM_PlainLinear)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_ChromaDetail420)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_ChromaDetail420RigPatches)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace mesocap
