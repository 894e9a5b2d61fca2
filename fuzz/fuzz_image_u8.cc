// 8-bit images through core/image_u8_io.h ReadImageU8, the fast path of fit-ptm: JPEG decoded by
// libjpeg(-turbo) from memory (colour, and converted to grey when fewer than 3 channels are
// asked for), anything else through OpenImageIO. Inputs are named .jpg, as RTI photos are.
#include "core/image_u8_io.h"
#include "fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto path = mesocap::fuzz::ScratchDir() / "input.jpg";
  mesocap::fuzz::WriteBytes(path, data, size);
  mesocap::fuzz::Run([&] {
    auto colour = mesocap::ReadImageU8(path, 4);
    mesocap::fuzz::Explain("ReadImageU8", colour.status());
    if (!colour.ok()) return;
    auto grey = mesocap::ReadImageU8(path, 1);
    mesocap::fuzz::Explain("ReadImageU8(grey)", grey.status());
  });
  return 0;
}
