// .ptm files (HP PTM 1.2, LRGB and RGB) through formats/ptm_file.h ReadPtmFile.
#include "formats/ptm_file.h"
#include "fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto path = mesocap::fuzz::ScratchDir() / "input.ptm";
  mesocap::fuzz::WriteBytes(path, data, size);
  mesocap::fuzz::Run([&] {
    mesocap::PtmQuantization quantization;
    auto ptm = mesocap::ReadPtmFile(path, &quantization);
    // Errors are fine; crashes, leaks, undefined behaviour and hangs are not.
    mesocap::fuzz::Explain("ReadPtmFile", ptm.status());
  });
  return 0;
}
