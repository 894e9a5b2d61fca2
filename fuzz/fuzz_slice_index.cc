// A slice index (SESSION/slices/index.json from calibrate, or a BTF folder's index.json from
// reconstruct) through core/slice_index.h ReadSliceIndex, the one reader that parses and
// validates every entry for reconstruct and synth. Parsing only: fuzz_slice_set and
// fuzz_btf_index follow the parsed index into the stages that read the slices.
#include "core/slice_index.h"
#include "fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto index = mesocap::fuzz::ScratchDir() / "index.json";
  mesocap::fuzz::WriteBytes(index, data, size);
  mesocap::fuzz::Run([&] {
    auto parsed = mesocap::ReadSliceIndex(index);
    mesocap::fuzz::Explain("ReadSliceIndex", parsed.status());
  });
  return 0;
}
