#include "core/exr_header_check.h"

#include <algorithm>
#include <cstring>
#include <fstream>
#include <map>
#include <string>

#include "core/image_io.h"

namespace mesocap {
namespace fs = std::filesystem;

namespace {

// Scanlines per compressed block, by the header's compression byte (OpenEXR's Compression enum:
// none, rle, zips, zip, piz, pxr24, b44, b44a, dwaa, dwab).
int64_t LinesPerChunk(int compression) {
  static constexpr int64_t kLines[] = {1, 1, 1, 16, 32, 16, 32, 32, 32, 256};
  return compression >= 0 && compression < 10 ? kLines[compression] : 1;
}

int64_t CeilDiv(int64_t a, int64_t b) { return b > 0 ? (a + b - 1) / b : 0; }

// One part's header as far as the sizes go. Layout (OpenEXR file format): attributes of
// name\0 type\0 int32 size, value; an empty name ends the header.
struct PartHeader {
  int64_t width = 0, height = 0, channels = 0;
  int compression = 0;
  int64_t tile_width = 0, tile_height = 0;  // 0: scanline part
  int64_t declared_chunks = -1;             // "chunkCount" of multi-part files

  int64_t Chunks() const {
    if (width <= 0 || height <= 0) return 0;
    // Tiled: at least the level-0 tiles (mipmap levels only add to it).
    if (tile_width > 0 && tile_height > 0) return CeilDiv(width, tile_width) * CeilDiv(height, tile_height);
    return std::max(declared_chunks, CeilDiv(height, LinesPerChunk(compression)));
  }
};

class HeaderReader {
 public:
  HeaderReader(const fs::path& path, std::ifstream& in, std::streamoff file_size)
      : path_(path), in_(in), file_size_(file_size) {}

  // Reads one header; false when the file ends or is too malformed to walk (OpenEXR's reader
  // then reports it), with *error set when a declared size is refused.
  bool Read(PartHeader* part, bool* empty, Status* error) {
    std::string name, type;
    *empty = true;
    while (ReadName(&name)) {
      if (name.empty()) return true;
      *empty = false;
      if (!ReadName(&type)) return false;
      int32_t size = 0;
      if (!in_.read(reinterpret_cast<char*>(&size), 4) || size < 0) return false;
      const std::streamoff value_start = in_.tellg();
      if (std::streamoff(size) > file_size_ - value_start) {
        *error = Malformed("attribute '" + name + "' declares " + std::to_string(size) + " bytes, more than the file holds");
        return false;
      }
      // OpenEXR reads a known type's own length whatever the declared size says: a size that
      // disagrees would put it somewhere else in the file than this walk (and its checks).
      if (const int natural = NaturalSize(type); natural >= 0 && size != natural) {
        *error = Malformed("attribute '" + name + "' of type " + type + " declares " + std::to_string(size) +
                           " bytes, not " + std::to_string(natural));
        return false;
      }
      if (!ReadValue(name, type, size, part, error)) return false;
      in_.seekg(value_start + size);
    }
    return false;
  }

 private:
  // The byte length of OpenEXR's fixed-size attribute types, -1 for the others.
  static int NaturalSize(const std::string& type) {
    static const std::map<std::string, int> sizes = {
        {"int", 4},      {"float", 4},     {"double", 8},      {"box2i", 16},       {"box2f", 16},
        {"v2i", 8},      {"v2f", 8},       {"v2d", 16},        {"v3i", 12},         {"v3f", 12},
        {"v3d", 24},     {"m33f", 36},     {"m33d", 72},       {"m44f", 64},        {"m44d", 128},
        {"compression", 1}, {"lineOrder", 1}, {"envmap", 1},   {"deepImageState", 1}, {"tiledesc", 9},
        {"rational", 8}, {"timecode", 8},  {"keycode", 28},    {"chromaticities", 32}};
    const auto it = sizes.find(type);
    return it == sizes.end() ? -1 : it->second;
  }

  Status Malformed(const std::string& what) const {
    return Status::Error(path_.string() + ": malformed OpenEXR header: " + what);
  }

  // A name as OpenEXR 3's Xdr::read(stream, 255, name) reads it, whatever the long-names flag
  // says: characters up to a NUL (read and dropped) or 256 of them, whichever comes first; the
  // next read starts right after. Reading exactly as OpenEXR does keeps this walk on
  // the bytes OpenEXR will take as sizes. False at the end of the file.
  bool ReadName(std::string* out) {
    out->clear();
    for (char c; in_.get(c);) {
      if (c == '\0') return true;
      out->push_back(c);
      if (out->size() > kMaxNameLength) return true;
    }
    return false;
  }

  template <typename T>
  bool ReadInt(T* value) { return bool(in_.read(reinterpret_cast<char*>(value), sizeof(T))); }

  bool ReadValue(const std::string& name, const std::string& type, int32_t size, PartHeader* part, Status* error) {
    if (name == "dataWindow" && type == "box2i") {
      int32_t box[4];
      if (!in_.read(reinterpret_cast<char*>(box), 16)) return false;
      part->width = int64_t(box[2]) - box[0] + 1;
      part->height = int64_t(box[3]) - box[1] + 1;
    } else if (name == "compression" && type == "compression") {
      uint8_t c = 0;
      if (!ReadInt(&c)) return false;
      part->compression = c;
    } else if (name == "tiles" && type == "tiledesc") {
      uint32_t tile[2];
      if (!ReadInt(&tile[0]) || !ReadInt(&tile[1])) return false;
      part->tile_width = tile[0];
      part->tile_height = tile[1];
    } else if (name == "chunkCount" && type == "int") {
      int32_t count = 0;
      if (!ReadInt(&count)) return false;
      part->declared_chunks = count;
    } else if (type == "chlist") {
      // name\0 then 16 bytes (pixel type, pLinear, reserved, x and y sampling) per channel, up
      // to an empty name; OpenEXR reads the list, not the declared size.
      std::string channel;
      int64_t length = 1;
      int64_t channels = 0;
      while (true) {
        if (!ReadName(&channel)) return false;
        if (channel.empty()) break;
        // OpenImageIO aborts the process on a pixel type OpenEXR does not know (found by
        // fuzz/fuzz_synth_files): 0 uint, 1 half, 2 float.
        int32_t pixel_type = 0;
        if (!ReadInt(&pixel_type)) return false;
        if (pixel_type < 0 || pixel_type > 2) {
          *error = Malformed("channel '" + channel + "' has pixel type " + std::to_string(pixel_type) +
                             " (OpenEXR knows 0 uint, 1 half, 2 float)");
          return false;
        }
        in_.seekg(12, std::ios::cur);
        length += int64_t(channel.size()) + 17;
        ++channels;
        if (length > size) break;
      }
      if (length != size) {
        *error = Malformed("channel list '" + name + "' declares " + std::to_string(size) + " bytes but holds " +
                           (length > size ? "more" : std::to_string(length)));
        return false;
      }
      if (name == "channels") part->channels = channels;
    } else if (type == "preview") {
      // Width and height, then 4 bytes a pixel: OpenEXR allocates what they declare.
      uint32_t w = 0, h = 0;
      if (!ReadInt(&w) || !ReadInt(&h)) return false;
      // In 128 bits: two 32-bit sides times 4 overflow 64.
      if (8 + 4 * static_cast<unsigned __int128>(w) * h != static_cast<unsigned __int128>(size)) {
        *error = Malformed("preview of " + std::to_string(w) + "x" + std::to_string(h) + " pixels in " +
                           std::to_string(size) + " bytes");
        return false;
      }
    }
    return bool(in_);
  }

  const fs::path& path_;
  std::ifstream& in_;
  std::streamoff file_size_;
  static constexpr size_t kMaxNameLength = 255;  // OpenEXR's Name::MAX_LENGTH
};

}  // namespace

Status CheckExrHeader(const fs::path& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  const std::streamoff file_size = in.tellg();
  in.seekg(0);
  unsigned char start[8];
  if (!in.read(reinterpret_cast<char*>(start), 8) || std::memcmp(start, "\x76\x2f\x31\x01", 4) != 0)
    return Status::Ok();
  const bool multi_part = start[5] & 0x10;  // version flags, bit 12
  HeaderReader reader(path, in, file_size);
  int64_t chunks = 0;  // offset-table entries over all parts
  for (int part_index = 0;; ++part_index) {
    PartHeader part;
    bool empty = true;
    Status error;
    const bool complete = reader.Read(&part, &empty, &error);
    if (!error.ok()) return error;
    if (!complete || empty) break;
    if (Status size = CheckImageSize(path, part.width, part.height, std::max<int64_t>(part.channels, 1));
        !size.ok())
      return size;
    chunks += part.Chunks();
    if (chunks > file_size / 8) break;  // already too many; and no sum over parts can overflow
    if (!multi_part) break;
  }
  // The offset table (8 bytes per chunk) follows the headers; OpenEXR allocates it whole.
  if (chunks > file_size / 8)
    return Status::Error(path.string() + ": malformed OpenEXR file: its headers declare " +
                         std::to_string(chunks) + " pixel blocks, whose offset table alone needs more than the " +
                         std::to_string(file_size) + " bytes the file holds");
  return Status::Ok();
}

}  // namespace mesocap
