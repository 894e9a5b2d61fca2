#include "core/image_io.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <cstring>
#include <set>

#include "core/atomic_file.h"
#include "core/exr_header_check.h"
#include "core/image_u8_io.h"
#include "core/image_codec.h"
#include "core/text_format.h"

namespace mesocap {
namespace fs = std::filesystem;

float SrgbToLinear(float v) {
  return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}

float LinearToSrgb(float v) {
  v = v > 0.0f ? std::min(v, 1.0f) : 0.0f;  // NaN -> 0
  return v <= 0.0031308f ? v * 12.92f : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

const std::array<float, 256>& SrgbDecodeTable() {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) t[i] = SrgbToLinear(i / 255.0f);
    return t;
  }();
  return table;
}

namespace {

// Encode table: linear value quantised to 1/65535 -> 8-bit sRGB code. Exact to the 8-bit
// result except where a value sits within 1/131070 of a rounding boundary.
const std::array<uint8_t, 65536>& SrgbEncodeTable() {
  static const std::array<uint8_t, 65536> table = [] {
    std::array<uint8_t, 65536> t{};
    for (int i = 0; i < 65536; ++i) t[i] = uint8_t(std::lround(LinearToSrgb(i / 65535.0f) * 255.0f));
    return t;
  }();
  return table;
}

// Total: NaN and values below 0 encode as 0, values above 1 as 255 (clamped before indexing).
uint8_t EncodeSrgb8(float linear) {
  if (!(linear > 0.0f)) return 0;
  if (linear >= 1.0f) return 255;
  return SrgbEncodeTable()[size_t(linear * 65535.0f + 0.5f)];
}

}  // namespace

namespace {
std::atomic<int64_t> max_image_pixels{kDefaultMaxImagePixels};
}  // namespace

void SetMaxImagePixels(int64_t pixels) { max_image_pixels = pixels; }
int64_t MaxImagePixels() { return max_image_pixels; }

// The most rows a decoder buffers at once (OpenImageIO's read_scanlines bands).
constexpr int64_t kMaxBufferedRows = 256;

Status CheckImageSize(const fs::path& path, int64_t width, int64_t height, int64_t channels) {
  if (width <= 0 || height <= 0) return Status::Error(path.string() + ": image has no pixels");
  const int64_t limit = MaxImagePixels();
  if (width > limit / height)
    return Status::Error(path.string() + ": the image declares " + std::to_string(width) + "x" +
                         std::to_string(height) + " pixels, more than the limit of " +
                         std::to_string(limit / 1000000) + " megapixels (--max-megapixels)");
  // OpenImageIO reads in bands of up to 256 rows whatever the height (a 2.6-million-pixel-wide,
  // 4-row EXR of 400 bytes asked for 2.7 GB): 256 rows must fit in the limit too.
  if (width > limit / kMaxBufferedRows)
    return Status::Error(path.string() + ": the image declares rows of " + std::to_string(width) +
                         " pixels, longer than the limit of " + std::to_string(limit / kMaxBufferedRows) +
                         " (--max-megapixels / 256 rows)");
  // Decoders buffer every declared channel: beyond 4, channels count against the limit too.
  if (channels > 4 && width * height / 4 > limit / channels)
    return Status::Error(path.string() + ": the image declares " + std::to_string(width) + "x" +
                         std::to_string(height) + " pixels of " + std::to_string(channels) +
                         " channels, more than the limit of " + std::to_string(limit / 1000000) +
                         " megapixels of 4 channels (--max-megapixels)");
  return Status::Ok();
}

namespace {

// The extensions of `list` ("format:ext,ext;format:ext...").
std::set<std::string> ExtensionsOf(const std::string& list) {
  std::set<std::string> all;
  for (size_t start = 0; start < list.size();) {
    size_t end = list.find(';', start);
    if (end == std::string::npos) end = list.size();
    const std::string entry = list.substr(start, end - start);
    const std::string exts = entry.substr(entry.find(':') + 1);
    for (size_t a = 0; a <= exts.size();) {
      size_t b = exts.find(',', a);
      if (b == std::string::npos) b = exts.size();
      if (b > a) all.insert("." + Lower(exts.substr(a, b - a)));
      a = b + 1;
    }
    start = end + 1;
  }
  return all;
}

}  // namespace

bool HasReadableImageExtension(const fs::path& path) {
  const std::string extension = Lower(path.extension().string());
  // The formats photos and our own outputs come in, answered without loading the codec.
  static const std::set<std::string> common = {".jpg", ".jpeg", ".png", ".tif", ".tiff", ".exr"};
  if (common.count(extension)) return true;
  static const std::set<std::string> all = [] {
    auto codec = LoadImageCodec();
    return codec.ok() ? ExtensionsOf((*codec)->ExtensionList()) : std::set<std::string>{};
  }();
  return all.count(extension) > 0;
}

Status CheckDeclaredImageSize(const fs::path& path) {
  if (Status exr = CheckExrHeader(path); !exr.ok()) return exr;
  return CheckJpegDeclaredSize(path);
}

PixelFormat DefaultFormatFor(const fs::path& path) {
  const std::string ext = Lower(path.extension().string());
  if (ext == ".jpg" || ext == ".jpeg") return PixelFormat::kUint8Srgb;
  if (ext == ".exr") return PixelFormat::kHalf;
  return PixelFormat::kUint16Linear;
}

namespace {

SampleType SampleTypeOf(PixelFormat format) {
  switch (format) {
    case PixelFormat::kUint8Srgb:
    case PixelFormat::kUint8Linear: return SampleType::kUint8;
    case PixelFormat::kUint16Linear: return SampleType::kUint16;
    case PixelFormat::kHalf: return SampleType::kHalf;
    case PixelFormat::kFloat: return SampleType::kFloat;
  }
  return SampleType::kFloat;
}

// The request to encode `image` with `options`; 8-bit encodings are made here, into *bytes, so
// they are exactly reproducible whatever the codec does.
StatusOr<EncodeRequest> EncodingOf(const fs::path& path, const Image& image, const ImageWriteOptions& options,
                                   PixelBytes* bytes) {
  if (image.empty()) return Status::Error(path.string() + ": refusing to write an empty image");
  const bool eight_bit = options.format == PixelFormat::kUint8Srgb || options.format == PixelFormat::kUint8Linear;
  if (eight_bit && Lower(path.extension().string()) == ".exr")  // the default format would silently sRGB-encode
    return Status::Error(path.string() + ": an OpenEXR file holds half or float values, not 8-bit ones (ask for "
                         "PixelFormat::kHalf or kFloat)");
  if (!options.channel_names.empty() && int(options.channel_names.size()) != image.channels())
    return Status::Error(path.string() + ": " + std::to_string(options.channel_names.size()) + " channel names for " +
                         std::to_string(image.channels()) + " channels");
  EncodeRequest request;
  request.width = image.width();
  request.height = image.height();
  request.channels = image.channels();
  request.stored = SampleTypeOf(options.format);
  request.jpeg_quality = options.jpeg_quality;
  request.exr_compression = options.exr_compression;
  request.attributes = options.attributes;
  request.channel_names = options.channel_names;
  request.type = SampleType::kFloat;
  request.pixels = image.data();
  if (eight_bit) {
    bytes->resize(image.size());
    const float* src = image.data();
    if (options.format == PixelFormat::kUint8Srgb) {
      for (size_t i = 0; i < bytes->size(); ++i) (*bytes)[i] = EncodeSrgb8(src[i]);
    } else {
      for (size_t i = 0; i < bytes->size(); ++i) (*bytes)[i] = uint8_t(std::lround(std::clamp(src[i], 0.0f, 1.0f) * 255.0f));
    }
    request.type = SampleType::kUint8;
    request.pixels = bytes->data();
  }
  return request;
}

// The codec to read `path` with, once the file exists, is not empty and declares a size within
// the limit.
StatusOr<ImageCodec*> CodecToRead(const fs::path& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return Status::Error(path.string() + ": no such file");
  if (fs::file_size(path, ec) == 0) return Status::Error(path.string() + ": empty file");
  if (Status size = CheckDeclaredImageSize(path); !size.ok()) return size;
  return LoadImageCodec();
}

}  // namespace

StatusOr<ImageInfo> ReadImageInfo(const fs::path& path, int part) {
  auto codec = CodecToRead(path);
  if (!codec.ok()) return codec.status();
  auto info = (*codec)->ReadInfo(path, part);
  if (!info.ok()) return info.status();
  if (Status size = CheckImageSize(path, info->width, info->height, info->channels); !size.ok()) return size;
  return info;
}

StatusOr<Image> ReadImage(const fs::path& path, const ImageReadOptions& options, ImageInfo* info_out) {
  auto codec = CodecToRead(path);
  if (!codec.ok()) return codec.status();
  Image image;
  PixelBytes bytes;  // 8-bit sRGB samples, linearised here
  ImageInfo info;
  auto target = [&](const ImageInfo& header) -> StatusOr<DecodeTarget> {
    info = header;
    if (header.channels <= 0) return Status::Error(path.string() + ": image has no pixels");
    if (Status size = CheckImageSize(path, header.width, header.height, header.channels); !size.ok()) return size;
    const int channels = std::min(header.channels, options.max_channels);
    image = Image(header.width, header.height, channels);
    if (header.stored_as_uint8 && options.linearize) {
      bytes.resize(image.size());
      return DecodeTarget{bytes.data(), SampleType::kUint8, channels};
    }
    return DecodeTarget{image.data(), SampleType::kFloat, channels};
  };
  MESOCAP_RETURN_IF_ERROR((*codec)->Read(path, options.part, target));
  if (!bytes.empty()) {
    const auto& table = SrgbDecodeTable();
    float* dst = image.data();
    for (size_t i = 0; i < bytes.size(); ++i) dst[i] = table[bytes[i]];
  }
  if (info_out) *info_out = std::move(info);
  return image;
}

Status WriteImage(const fs::path& path, const Image& image, const ImageWriteOptions& options) {
  PixelBytes bytes;
  auto request = EncodingOf(path, image, options, &bytes);
  if (!request.ok()) return request.status();
  auto codec = LoadImageCodec();
  if (!codec.ok()) return codec.status();
  return WriteFileAtomically(path, [&](const fs::path& temp) { return (*codec)->Write(temp, path, *request); });
}

Status WriteMultiPartExr(const fs::path& path, const std::vector<ExrPartHeader>& parts,
                         const std::function<StatusOr<Image>(int k)>& pixels) {
  std::vector<EncodeRequest> headers;
  for (const ExrPartHeader& part : parts) {
    if (part.options.format != PixelFormat::kHalf && part.options.format != PixelFormat::kFloat)
      return Status::Error(path.string() + ": OpenEXR parts hold half or float samples");
    PixelBytes unused;
    auto header = EncodingOf(path, Image(part.width, part.height, part.channels), part.options, &unused);
    if (!header.ok()) return header.status();
    header->part_name = part.name;
    header->pixels = nullptr;
    headers.push_back(std::move(*header));
  }
  auto codec = LoadImageCodec();
  if (!codec.ok()) return codec.status();
  Image current;  // the one part held
  auto part_pixels = [&](int k) -> StatusOr<EncodeRequest> {
    auto image = pixels(k);
    if (!image.ok()) return image.status();
    current = std::move(*image);
    EncodeRequest request = headers[size_t(k)];
    request.width = current.width();
    request.height = current.height();
    request.channels = current.channels();
    request.type = SampleType::kFloat;
    request.pixels = current.data();
    return request;
  };
  return WriteFileAtomically(path, [&](const fs::path& temp) { return (*codec)->WriteExrParts(temp, path, headers, part_pixels); });
}

}  // namespace mesocap
