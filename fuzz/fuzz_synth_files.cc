// The files synthesis writes and reads back: a texture-coordinate map (synth/synth_map.h
// ReadSynthMap, what synth-apply takes) and a texton analysis (synth/texton_analysis.h
// ReadTextonAnalysis, what synth --analysis takes), both OpenEXR with attributes the readers trust
// only after checking.
#include "core/image_io.h"
#include "fuzz/fuzz_support.h"
#include "synth/synth_map.h"
#include "synth/texton_analysis.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  mesocap::SetMaxImagePixels(4000000);  // as fuzz_image: legitimate images stay far below the RSS limit
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto path = mesocap::fuzz::ScratchDir() / "input.exr";
  mesocap::fuzz::WriteBytes(path, data, size);
  mesocap::fuzz::Run([&] {
    auto map = mesocap::ReadSynthMap(path);
    mesocap::fuzz::Explain("ReadSynthMap", map.status());
    auto textons = mesocap::ReadTextonAnalysis(path);
    mesocap::fuzz::Explain("ReadTextonAnalysis", textons.status());
  });
  return 0;
}
