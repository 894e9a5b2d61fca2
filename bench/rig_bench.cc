// Google Benchmark: the virtual rig's hot paths. The whole-session figure is bench/simulate_bench.sh.
#include <benchmark/benchmark.h>

#include "capture/rig_render.h"

namespace mesocap {
namespace {

void BM_TrueBtfSlice256(benchmark::State& state) {
  auto material = Material::Create("stones");
  for (auto _ : state) {
    Image slice = RenderTrueBtfSlice(*material, {60, 30, 60, 200, 256});
    benchmark::DoNotOptimize(slice.data());
  }
  state.SetItemsProcessed(state.iterations() * 256 * 256);
}
BENCHMARK(BM_TrueBtfSlice256)->Unit(benchmark::kMillisecond);

void BM_FlashShot3000x2000(benchmark::State& state) {
  RigOptions o;
  o.shots = 2;
  o.calib_shots = 1;
  auto scene = MakeRigScene(o);
  auto material = Material::Create(o.material);
  RigRenderer renderer(*scene, *material);
  renderer.Prepare();
  int k = 0;
  for (auto _ : state) {
    Image im = renderer.RenderShotLinear(k++ % 2);
    benchmark::DoNotOptimize(im.data());
  }
}
BENCHMARK(BM_FlashShot3000x2000)->Unit(benchmark::kMillisecond);

void BM_CheckerboardShot3000x2000(benchmark::State& state) {
  RigOptions o;
  o.shots = 1;
  o.calib_shots = 1;
  auto scene = MakeRigScene(o);
  auto material = Material::Create("flat");
  RigRenderer renderer(*scene, *material);
  for (auto _ : state) {
    Image im = renderer.RenderCalibLinear(0);
    benchmark::DoNotOptimize(im.data());
  }
}
BENCHMARK(BM_CheckerboardShot3000x2000)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace mesocap
