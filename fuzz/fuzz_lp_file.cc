// RTI light-position files (.lp) through formats/lp_file.h ReadLpFile. The folder holds a few
// (empty) image files so that lines naming them resolve, as in a real RTI folder.
#include "formats/lp_file.h"
#include "fuzz/fuzz_support.h"

namespace {

const std::filesystem::path& LpFolder() {
  static const std::filesystem::path folder = [] {
    const auto dir = mesocap::fuzz::ScratchDir() / "rti";
    std::filesystem::create_directories(dir / "photos");
    for (const char* name : {"img_01.jpg", "img_02.jpg", "img 03.png", "photos/img_04.tif"})
      mesocap::fuzz::WriteText(dir / name, "");
    return dir;
  }();
  return folder;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto path = LpFolder() / "lights.lp";
  mesocap::fuzz::WriteBytes(path, data, size);
  mesocap::fuzz::Run([&] {
    auto strict = mesocap::ReadLpFile(path, /*require_images_exist=*/true);
    mesocap::fuzz::Explain("ReadLpFile", strict.status());
    auto lenient = mesocap::ReadLpFile(path, /*require_images_exist=*/false);
    mesocap::fuzz::Explain("ReadLpFile(lenient)", lenient.status());
  });
  return 0;
}
