// All image file I/O: JPEG, PNG, TIFF, camera RAW (libraw), OpenEXR, through OpenImageIO loaded on
// first use (core/image_codec.h).
// Encoding rule (docs/formats.md): 8-bit files hold sRGB-encoded values, 16-bit and float files
// hold linear values. Reading returns linear floats in [0,1] for integer files unless asked not to.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <variant>
#include <vector>

#include "core/image.h"
#include "core/status.h"

namespace mesocap {

using AttributeValue = std::variant<int, float, std::string>;
using ImageAttributes = std::map<std::string, AttributeValue>;

// kUint8Linear stores round(255 v) as is: data textures (normal maps, roughness) that are not
// colours.
enum class PixelFormat { kUint8Srgb, kUint8Linear, kUint16Linear, kHalf, kFloat };

struct ImageWriteOptions {
  // kUint8Srgb for JPEG/8-bit PNG, kUint16Linear for PNG/TIFF, kHalf or kFloat for EXR.
  PixelFormat format = PixelFormat::kUint8Srgb;
  int jpeg_quality = 95;
  std::string exr_compression = "zip";  // zip, piz, none
  ImageAttributes attributes{};         // EXR: stored as header attributes; others: metadata
  std::vector<std::string> channel_names{};  // EXR: names of the channels (empty: R, G, B, A, ...)
};

struct ImageReadOptions {
  bool linearize = true;  // decode sRGB 8-bit files to linear
  int max_channels = 4;   // drop alpha and extra channels beyond this many
  int part = 0;           // multi-part OpenEXR: which part
};

struct ImageInfo {
  int width = 0, height = 0, channels = 0;
  std::string format_name;   // "jpeg", "png", "openexr", "raw", ...
  int bits_per_sample = 0;   // 8, 16, 32
  bool stored_as_uint8 = false;  // samples are 8-bit unsigned integers in the file
  ImageAttributes attributes;  // every header/EXIF attribute OpenImageIO reports
  std::vector<std::string> channel_names;
};

// The largest image, in pixels, any reader allocates: a header declaring more is refused before
// a byte is allocated, so a tiny crafted file cannot ask for gigabytes. 250 MP is above every
// camera sensor (150 MP medium format); 250 MP of 4 float channels is 4 GB. Process-wide; the
// CLI's --max-megapixels sets it.
inline constexpr int64_t kDefaultMaxImagePixels = 250000000;
void SetMaxImagePixels(int64_t pixels);
int64_t MaxImagePixels();
// Ok if a width x height image is within the limit, 256 of its rows too (decoders buffer bands
// of rows), and its channels beyond 4 (which decoders buffer too) within 4 channels' worth of
// it; otherwise an error naming `path`.
Status CheckImageSize(const std::filesystem::path& path, int64_t width, int64_t height, int64_t channels = 1);
// The same from the file's own header, read before any decoder opens it, for the formats whose
// decoders allocate from the declared size while opening (OpenEXR: core/exr_header_check.h).
Status CheckDeclaredImageSize(const std::filesystem::path& path);

// True when OpenImageIO has a reader for the file's extension (any case): JPEG, PNG, TIFF, EXR,
// camera RAW, TGA, BMP, ... Lists of photos in a folder are filtered with it.
bool HasReadableImageExtension(const std::filesystem::path& path);

// Reads header only (cheap): size, format, EXIF. Error names the file.
StatusOr<ImageInfo> ReadImageInfo(const std::filesystem::path& path, int part = 0);
// Reads the whole image. Error names the file and what was wrong (truncated, not an image ...).
StatusOr<Image> ReadImage(const std::filesystem::path& path, const ImageReadOptions& options = {},
                          ImageInfo* info = nullptr);
// Writes atomically: a temp file beside `path`, fsync, rename. Nothing is left half-written.
Status WriteImage(const std::filesystem::path& path, const Image& image,
                  const ImageWriteOptions& options = {});

// One part of a multi-part OpenEXR, as its header declares it.
struct ExrPartHeader {
  std::string name;
  int width = 0, height = 0, channels = 0;
  ImageWriteOptions options;  // format kHalf or kFloat, compression, attributes, channel names
};
// Writes a multi-part OpenEXR atomically: every part's header, then the pixels of part k from
// `pixels(k)`, one part at a time (only one is held). Each image must match its header.
Status WriteMultiPartExr(const std::filesystem::path& path, const std::vector<ExrPartHeader>& parts,
                         const std::function<StatusOr<Image>(int k)>& pixels);

// Picks a sensible format from the extension: .jpg/.jpeg -> 8-bit sRGB, .png/.tif -> 16-bit
// linear, .exr -> half.
PixelFormat DefaultFormatFor(const std::filesystem::path& path);

// sRGB transfer curve (IEC 61966-2-1), per value.
float SrgbToLinear(float v);
float LinearToSrgb(float v);
// SrgbToLinear of every 8-bit code v / 255.
const std::array<float, 256>& SrgbDecodeTable();

}  // namespace mesocap
