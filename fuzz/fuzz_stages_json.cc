// SESSION/stages.json through core/stage_cache.h StageCache::Open, as `mesocap process` and
// export read it, then every question they ask of it (why a stage runs, its outputs' hash, whether
// one stage was made from another's current outputs) on the scratch session.
#include "core/session_layout.h"
#include "core/stage_cache.h"
#include "fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto session = mesocap::fuzz::ScratchDir();
  mesocap::fuzz::WriteBytes(mesocap::SessionLayout(session).stage_cache(), data, size);
  mesocap::fuzz::Run([&] {
    auto cache = mesocap::StageCache::Open(session);
    mesocap::fuzz::Explain("StageCache::Open", cache.status());
    if (!cache.ok()) return;
    for (const char* stage : {"calibrate", "resample", "fit-ptm", "reconstruct", "synth", "export"}) {
      (void)cache->WhyRun(stage, "0123456789abcdef0123456789abcdef", 1);
      (void)cache->OutputsHash(stage);
    }
    (void)cache->MadeFromCurrent("synth", "reconstruct");
  });
  return 0;
}
