// calibrate --marked-corners FILE through calib/marked_corners.h ReadMarkedCorners, for a rig of
// three boards (ids 0-2) and 1500 x 1000 photographs, as calib/calibrate.cc reads it.
#include "calib/marked_corners.h"
#include "fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto path = mesocap::fuzz::ScratchDir() / "marked.json";
  mesocap::fuzz::WriteBytes(path, data, size);
  static const std::vector<mesocap::LayoutBoard> boards = [] {
    std::vector<mesocap::LayoutBoard> b(3);
    for (int k = 0; k < 3; ++k) b[k].id = k, b[k].size_m = 0.1, b[k].patch_m = 0.06;
    return b;
  }();
  mesocap::fuzz::Run([&] {
    auto marked = mesocap::ReadMarkedCorners(path, boards, 1500, 1000);
    mesocap::fuzz::Explain("ReadMarkedCorners", marked.status());
  });
  return 0;
}
