// The file name an image input is written under: OpenImageIO tries the reader its extension
// names first, so inputs are named by their magic bytes as a camera or writer would name them
// (unknown bytes get an unknown extension, which mesocap refuses: only the extension's reader
// opens a file, core/oiio_input.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>

namespace mesocap::fuzz {

inline std::string ImageFileName(const uint8_t* data, size_t size) {
  auto starts = [&](const char* magic, size_t n) { return size >= n && std::memcmp(data, magic, n) == 0; };
  if (starts("\xFF\xD8\xFF", 3)) return "input.jpg";
  if (starts("\x89PNG", 4)) return "input.png";
  if (starts("II*\0", 4) || starts("MM\0*", 4)) return "input.tif";
  if (starts("\x76\x2F\x31\x01", 4)) return "input.exr";
  if (starts("#?RADIANCE", 10) || starts("#?RGBE", 6)) return "input.hdr";
  if (starts("P", 1) && size >= 2 && data[1] >= '1' && data[1] <= '6') return "input.pnm";
  if (starts("BM", 2)) return "input.bmp";
  return "input.img";
}

}  // namespace mesocap::fuzz
