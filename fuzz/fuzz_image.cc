// Image files through the float read path every stage uses: core/image_io.h ReadImageInfo
// (header only) and ReadImage (pixels, linearised, at most 4 channels), as OpenImageIO decodes
// them (JPEG, PNG, TIFF, OpenEXR, ...). A header declaring a huge image must be refused, not
// allocated: libFuzzer's -rss_limit_mb / -malloc_limit_mb report it as out-of-memory.
#include "core/image_io.h"
#include "fuzz/fuzz_support.h"
#include "fuzz/image_name.h"

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
  const auto path = mesocap::fuzz::ScratchDir() / mesocap::fuzz::ImageFileName(data, size);
  mesocap::fuzz::WriteBytes(path, data, size);
  mesocap::fuzz::Run([&] {
    auto info = mesocap::ReadImageInfo(path);
    mesocap::fuzz::Explain("ReadImageInfo", info.status());
    if (!info.ok()) return;
    mesocap::ImageInfo read_info;
    auto image = mesocap::ReadImage(path, {}, &read_info);
    mesocap::fuzz::Explain("ReadImage", image.status());
  });
  std::error_code ec;
  std::filesystem::remove(path, ec);  // the next input may get another extension
  return 0;
}
