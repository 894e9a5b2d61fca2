// The image formats OpenImageIO reads and writes (PNG, TIFF, OpenEXR, camera RAW, ...), behind an
// interface whose one implementation lives in a module loaded on first use (core/oiio_codec.cc,
// libmesocap_oiio.so). OpenImageIO brings about 260 shared libraries (GDAL, DICOM, ffmpeg, ...):
// linked into the executable they cost 0.2 s before main on every run, also for a command that
// only reads JPEGs (decoded with libjpeg, core/image_u8_io.cc) or none at all.
//
// The module holds no state of its own: size limits are decided by the caller through the
// `target` callback before a pixel is allocated, and pixels go into buffers the caller owns.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "core/image_io.h"
#include "core/status.h"

namespace mesocap {

enum class SampleType { kUint8, kUint16, kHalf, kFloat };

// Where a decoder puts the pixels: `channels` interleaved samples of `type` per pixel, rows
// contiguous, owned by the caller.
struct DecodeTarget {
  void* pixels = nullptr;
  SampleType type = SampleType::kFloat;
  int channels = 0;
};

// One image to encode: pixels as interleaved samples of `type`, stored in the file as `stored`.
struct EncodeRequest {
  int width = 0, height = 0, channels = 0;
  SampleType type = SampleType::kFloat;   // of `pixels`
  SampleType stored = SampleType::kFloat; // in the file
  const void* pixels = nullptr;
  std::string part_name;                  // multi-part EXR: the part's name
  int jpeg_quality = 95;
  std::string exr_compression = "zip";
  ImageAttributes attributes;
  std::vector<std::string> channel_names;  // empty: the writer's defaults
};

class ImageCodec {
 public:
  virtual ~ImageCodec() = default;
  // "format:ext,ext;format:ext..." over every reader.
  virtual std::string ExtensionList() = 0;
  // Header of subimage (EXR part) `part`: size, format, attributes. Errors name `path`.
  virtual StatusOr<ImageInfo> ReadInfo(const std::filesystem::path& path, int part) = 0;
  // Decodes subimage `part` into the buffer `target` returns for its header (or the error it
  // returns, e.g. a size over the limit, before anything is allocated).
  virtual Status Read(const std::filesystem::path& path, int part,
                      const std::function<StatusOr<DecodeTarget>(const ImageInfo&)>& target) = 0;
  // Writes `file` in the format `path`'s extension names (`file` may be a temp name for it).
  virtual Status Write(const std::filesystem::path& file, const std::filesystem::path& path,
                       const EncodeRequest& image) = 0;
  // A multi-part OpenEXR: every part's header first (`parts`, pixels unused), then each part's
  // pixels from `pixels(k)`, one at a time, so only one part is ever held.
  virtual Status WriteExrParts(const std::filesystem::path& file, const std::filesystem::path& path,
                               const std::vector<EncodeRequest>& parts,
                               const std::function<StatusOr<EncodeRequest>(int part)>& pixels) = 0;
};

// The module's one entry point, an ImageCodec* () (core/module_loader.h LoadModuleObject).
inline constexpr const char* kImageCodecFactorySymbol = "MesocapImageCodec";
inline constexpr const char* kImageCodecModuleName = "libmesocap_oiio.so";

// The codec, loaded on the first call (thread-safe): the module beside the executable, else the
// one the build made. An error says where it looked.
StatusOr<ImageCodec*> LoadImageCodec();

}  // namespace mesocap
