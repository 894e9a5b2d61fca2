// Google Benchmark: the statistical BTF's inner loop, a steerable-pyramid build + collapse of one
// plane (about 3 * 6561 of each for an 81x81 BTF) and histogram matching of a band.
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "reconstruct/quantiles.h"
#include "reconstruct/steerable_pyramid.h"

namespace mesocap {
namespace {

std::vector<float> NoisePlane(int size) {
  std::mt19937 rng(size);
  std::normal_distribution<float> normal(0, 1);
  std::vector<float> plane(size_t(size) * size);
  for (float& v : plane) v = normal(rng);
  return plane;
}

void BM_PyramidBuildCollapse(benchmark::State& state) {
  const int size = int(state.range(0));
  const std::vector<float> plane = NoisePlane(size);
  for (auto _ : state) {
    const SteerablePyramid pyramid = BuildSteerablePyramid(plane.data(), size, size);
    std::vector<float> back = CollapseSteerablePyramid(pyramid);
    benchmark::DoNotOptimize(back.data());
  }
  state.SetItemsProcessed(state.iterations() * size * size);
}
BENCHMARK(BM_PyramidBuildCollapse)->Arg(256)->Arg(512)->Unit(benchmark::kMillisecond);

void BM_PyramidBuild(benchmark::State& state) {
  const int size = int(state.range(0));
  const std::vector<float> plane = NoisePlane(size);
  for (auto _ : state) {
    SteerablePyramid pyramid = BuildSteerablePyramid(plane.data(), size, size);
    benchmark::DoNotOptimize(pyramid.bands.data());
  }
}
BENCHMARK(BM_PyramidBuild)->Arg(256)->Unit(benchmark::kMillisecond);

void BM_PyramidCollapse(benchmark::State& state) {
  const int size = int(state.range(0));
  const std::vector<float> plane = NoisePlane(size);
  const SteerablePyramid pyramid = BuildSteerablePyramid(plane.data(), size, size);
  for (auto _ : state) {
    std::vector<float> back = CollapseSteerablePyramid(pyramid);
    benchmark::DoNotOptimize(back.data());
  }
}
BENCHMARK(BM_PyramidCollapse)->Arg(256)->Unit(benchmark::kMillisecond);

void BM_MatchToInverseCdf(benchmark::State& state) {
  const std::vector<float> values = NoisePlane(256);  // 65536 values
  std::vector<float> target_samples = NoisePlane(255);
  for (float& v : target_samples) v = v * v;
  const InverseCdf target = InverseCdfOf(target_samples);
  std::vector<float> work;
  for (auto _ : state) {
    work = values;
    MatchToInverseCdf(work, target);
    benchmark::DoNotOptimize(work.data());
  }
  state.SetItemsProcessed(state.iterations() * values.size());
}
BENCHMARK(BM_MatchToInverseCdf)->Unit(benchmark::kMicrosecond);

void BM_InverseCdfOf(benchmark::State& state) {
  const std::vector<float> values = NoisePlane(256);
  for (auto _ : state) {
    InverseCdf q = InverseCdfOf(values);
    benchmark::DoNotOptimize(q.values.data());
  }
  state.SetItemsProcessed(state.iterations() * values.size());
}
BENCHMARK(BM_InverseCdfOf)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace mesocap
