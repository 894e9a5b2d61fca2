// Image files through the float read path every stage uses: core/image_io.h ReadImageInfo
// (header only) and ReadImage (pixels, linearised, at most 4 channels), as OpenImageIO decodes
// them (JPEG, PNG, TIFF, OpenEXR, ...). A header declaring a huge image must be refused, not
// allocated: libFuzzer's -rss_limit_mb / -malloc_limit_mb report it as out-of-memory.
#include "core/image_io.h"
#include "fuzz/fuzz_support.h"
#include "fuzz/image_name.h"

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
