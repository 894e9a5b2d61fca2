// 8-bit images through core/image_u8_io.h ReadImageU8, the fast path of fit-ptm: JPEG decoded by
// libjpeg(-turbo) from memory (colour, and converted to grey when fewer than 3 channels are
// asked for), anything else through OpenImageIO; and a JPEG with subsampled colour through
// calibrate's shot reading, its colour detail restored (core/chroma_detail.h). Inputs are named
// .jpg, as RTI photos are.
#include "core/chroma_detail.h"
#include "core/image_io.h"
#include "core/image_u8_io.h"
#include "fuzz/fuzz_support.h"

// The pixel cap scaled to libFuzzer's 2 GB RSS limit: a legitimate image at the default 250 MP
// cap is 4 GB of floats, which would be reported as out-of-memory without being a bug. At 4 MP
// every image the readers accept takes under 100 MB (64 MB of floats, the 8-bit copy, a band of
// 256 rows), far below the limit even with ASan's quarantine keeping freed memory resident;
// any out-of-memory left is an allocation the cap failed to bound. The cap's value does not
// change which code runs.
extern "C" int LLVMFuzzerInitialize(int*, char***) {
  mesocap::SetMaxImagePixels(4000000);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto path = mesocap::fuzz::ScratchDir() / "input.jpg";
  mesocap::fuzz::WriteBytes(path, data, size);
  mesocap::fuzz::Run([&] {
    auto colour = mesocap::ReadImageU8(path, 4);
    mesocap::fuzz::Explain("ReadImageU8", colour.status());
    if (!colour.ok()) return;
    auto grey = mesocap::ReadImageU8(path, 1);
    mesocap::fuzz::Explain("ReadImageU8(grey)", grey.status());
    auto jpeg = mesocap::JpegRowReader::Open(path, 3);
    if (!jpeg.ok() || !*jpeg || (*jpeg)->channels() != 3 || !mesocap::ChromaDetailRestorable((*jpeg)->chroma_factors())) return;
    auto srgb = (*jpeg)->ReadAll();
    if (!srgb.ok()) return;
    mesocap::LinearWithChromaDetail(*srgb, (*jpeg)->chroma_factors());
    // Regions as resampling asks for them: partly outside the image, overlapping, empty.
    const int w = srgb->width(), h = srgb->height();
    const mesocap::PixelRect regions[] = {{-3, -5, w / 2 + 1, h / 3 + 1}, {w / 3, h / 4, w + 7, h + 2}, {w, h, w + 2, h + 2}};
    mesocap::LinearWithChromaDetail(*srgb, (*jpeg)->chroma_factors(), 4, regions);
  });
  return 0;
}
