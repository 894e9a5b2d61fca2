// Small slice images for the index fuzzers: the index under test (slices/index.json or a BTF
// folder's index.json) names files, and these give it real ones to name, of the kinds a folder
// may hold (RGB half EXR of two sizes, grey and RGBA PNG, a non-square slice, a corrupt file).
#pragma once

#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "core/image.h"
#include "core/image_io.h"
#include "fuzz/fuzz_support.h"

namespace mesocap::fuzz {

// Files (relative to the returned folder):
//   board_00/shot_0001.exr .. shot_0004.exr   16x16 RGB half, different patterns
//   board_01/shot_0001.exr .. shot_0003.exr   16x16 RGB half
//   big/shot_0001.exr                         32x32 RGB half
//   odd/shot_0001.exr                         16x8 RGB half
//   grey/shot_0001.png                        16x16 grey 16-bit PNG
//   rgba/shot_0001.png                        16x16 RGBA 16-bit PNG
//   bad/shot_0001.exr                         not an image
inline const std::filesystem::path& SliceFolder() {
  static const std::filesystem::path folder = [] {
    const auto dir = ScratchDir() / "slices";
    auto write = [&](const std::string& name, int w, int h, int channels, int seed) {
      std::filesystem::create_directories((dir / name).parent_path());
      Image image(w, h, channels);
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
          for (int c = 0; c < channels; ++c)
            image.at(x, y, c) = 0.5f + 0.4f * std::sin(0.7f * x * (seed + 1) + 1.3f * y + c + seed);
      ImageWriteOptions options;
      options.format = name.ends_with(".exr") ? PixelFormat::kHalf : PixelFormat::kUint16Linear;
      if (!WriteImage(dir / name, image, options).ok()) std::abort();
    };
    for (int k = 1; k <= 4; ++k) write("board_00/shot_000" + std::to_string(k) + ".exr", 16, 16, 3, k);
    for (int k = 1; k <= 3; ++k) write("board_01/shot_000" + std::to_string(k) + ".exr", 16, 16, 3, 10 + k);
    write("big/shot_0001.exr", 32, 32, 3, 20);
    write("odd/shot_0001.exr", 16, 8, 3, 21);
    write("grey/shot_0001.png", 16, 16, 1, 22);
    write("rgba/shot_0001.png", 16, 16, 4, 23);
    std::filesystem::create_directories(dir / "bad");
    WriteText(dir / "bad/shot_0001.exr", "not an image\n");
    return dir;
  }();
  return folder;
}

}  // namespace mesocap::fuzz
