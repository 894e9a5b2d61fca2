#include "core/image_io.h"

#include <OpenImageIO/imageio.h>

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
#include "core/oiio_input.h"

namespace mesocap {
namespace fs = std::filesystem;
namespace oiio = OIIO;

float SrgbToLinear(float v) {
  return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}

float LinearToSrgb(float v) {
  v = v > 0.0f ? std::min(v, 1.0f) : 0.0f;  // NaN -> 0
  return v <= 0.0031308f ? v * 12.92f : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

namespace {

// 256-entry decode table: 8-bit sRGB code -> linear.
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

const std::array<float, 256>& SrgbDecodeTable() {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) t[i] = SrgbToLinear(i / 255.0f);
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

std::string Lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

ImageAttributes AttributesOf(const oiio::ImageSpec& spec) {
  ImageAttributes out;
  for (const auto& p : spec.extra_attribs) {
    const oiio::TypeDesc t = p.type();
    if (t == oiio::TypeInt || t == oiio::TypeUInt) {
      out[p.name().string()] = p.get_int();
    } else if (t == oiio::TypeFloat) {
      out[p.name().string()] = p.get_float();
    } else {
      out[p.name().string()] = p.get_string();
    }
  }
  return out;
}

void ApplyAttributes(const ImageAttributes& attributes, oiio::ImageSpec* spec) {
  for (const auto& [name, value] : attributes) {
    if (const int* i = std::get_if<int>(&value)) spec->attribute(name, *i);
    if (const float* f = std::get_if<float>(&value)) spec->attribute(name, *f);
    if (const std::string* s = std::get_if<std::string>(&value)) spec->attribute(name, *s);
  }
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

bool HasReadableImageExtension(const fs::path& path) {
  // OIIO's "extension_list" is "format:ext,ext;format:ext...", over every reader plugin.
  static const std::set<std::string> extensions = [] {
    std::set<std::string> all;
    std::string list = oiio::get_string_attribute("extension_list");
    for (size_t start = 0; start < list.size();) {
      size_t end = list.find(';', start);
      if (end == std::string::npos) end = list.size();
      const std::string entry = list.substr(start, end - start);
      std::string exts = entry.substr(entry.find(':') + 1);
      for (size_t a = 0; a <= exts.size();) {
        size_t b = exts.find(',', a);
        if (b == std::string::npos) b = exts.size();
        if (b > a) all.insert("." + Lower(exts.substr(a, b - a)));
        a = b + 1;
      }
      start = end + 1;
    }
    return all;
  }();
  return extensions.count(Lower(path.extension().string())) > 0;
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

std::unique_ptr<oiio::ImageInput> OpenImageForExtension(const fs::path& path, const oiio::ImageSpec* config,
                                                       std::string* error) {
  const std::string extension = path.extension().string();
  auto in = extension.size() > 1 ? oiio::ImageInput::create(extension.substr(1)) : nullptr;
  if (!in) {
    *error = extension.size() > 1 ? "not an image: no image reader for files named *" + extension
                                  : std::string("not an image: no file extension to choose an image reader by");
    oiio::geterror();  // drop OpenImageIO's pending message
    return nullptr;
  }
  oiio::ImageSpec spec;
  const bool opened = config ? in->open(path.string(), spec, *config) : in->open(path.string(), spec);
  if (!opened) {
    *error = in->geterror();
    if (error->empty()) *error = "not a readable " + std::string(in->format_name()) + " file";
    return nullptr;
  }
  return in;
}

StatusOr<ImageInfo> ReadImageInfo(const fs::path& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return Status::Error(path.string() + ": no such file");
  if (fs::file_size(path, ec) == 0) return Status::Error(path.string() + ": empty file");
  if (Status size = CheckDeclaredImageSize(path); !size.ok()) return size;
  oiio::ImageSpec config;
  config.attribute("raw:ColorSpace", "linear");
  std::string why;
  auto in = OpenImageForExtension(path, &config, &why);
  if (!in) return Status::Error(path.string() + ": " + why);
  const oiio::ImageSpec& spec = in->spec();
  if (Status size = CheckImageSize(path, spec.width, spec.height, spec.nchannels); !size.ok()) return size;
  ImageInfo info;
  info.width = spec.width;
  info.height = spec.height;
  info.channels = spec.nchannels;
  info.format_name = in->format_name();
  info.bits_per_sample = int(spec.format.size()) * 8;
  if (const int bps = spec.get_int_attribute("oiio:BitsPerSample", 0); bps > 0)
    info.bits_per_sample = bps;
  info.attributes = AttributesOf(spec);
  info.channel_names.assign(spec.channelnames.begin(), spec.channelnames.end());
  in->close();
  return info;
}

StatusOr<Image> ReadImage(const fs::path& path, const ImageReadOptions& options, ImageInfo* info_out) {
  auto info = ReadImageInfo(path);
  if (!info.ok()) return info.status();
  oiio::ImageSpec config;
  config.attribute("raw:ColorSpace", "linear");
  std::string why;
  auto in = OpenImageForExtension(path, &config, &why);
  if (!in) return Status::Error(path.string() + ": " + why);
  const oiio::ImageSpec& spec = in->spec();
  if (spec.nchannels <= 0) return Status::Error(path.string() + ": image has no pixels");
  if (Status size = CheckImageSize(path, spec.width, spec.height, spec.nchannels); !size.ok()) return size;
  const int channels = std::min(spec.nchannels, options.max_channels);
  const bool is_8bit = spec.format == oiio::TypeDesc::UINT8;
  Image image(spec.width, spec.height, channels);
  bool ok = true;
  if (is_8bit && options.linearize) {
    std::vector<uint8_t> bytes(size_t(spec.width) * spec.height * channels);
    ok = in->read_image(0, 0, 0, channels, oiio::TypeDesc::UINT8, bytes.data());
    const auto& table = SrgbDecodeTable();
    float* dst = image.data();
    for (size_t i = 0; i < bytes.size(); ++i) dst[i] = table[bytes[i]];
  } else {
    ok = in->read_image(0, 0, 0, channels, oiio::TypeDesc::FLOAT, image.data());
  }
  // libjpeg reports a truncated file as a warning and pads with grey: treat it as corrupt.
  std::string err = in->geterror();
  in->close();
  if (!ok || !err.empty()) {
    if (err.empty()) err = "could not decode pixels";
    return Status::Error(path.string() + ": " + err);
  }
  if (info_out) *info_out = *info;
  return image;
}

Status WriteImage(const fs::path& path, const Image& image, const ImageWriteOptions& options) {
  if (image.empty()) return Status::Error(path.string() + ": refusing to write an empty image");
  oiio::TypeDesc type = oiio::TypeDesc::UINT8;
  switch (options.format) {
    case PixelFormat::kUint8Srgb: type = oiio::TypeDesc::UINT8; break;
    case PixelFormat::kUint8Linear: type = oiio::TypeDesc::UINT8; break;
    case PixelFormat::kUint16Linear: type = oiio::TypeDesc::UINT16; break;
    case PixelFormat::kHalf: type = oiio::TypeDesc::HALF; break;
    case PixelFormat::kFloat: type = oiio::TypeDesc::FLOAT; break;
  }
  oiio::ImageSpec spec(image.width(), image.height(), image.channels(), type);
  const std::string ext = Lower(path.extension().string());
  if (ext == ".jpg" || ext == ".jpeg") spec.attribute("Compression", "jpeg:" + std::to_string(options.jpeg_quality));
  if (ext == ".exr") spec.attribute("compression", options.exr_compression);
  ApplyAttributes(options.attributes, &spec);
  if (!options.channel_names.empty()) {
    if (int(options.channel_names.size()) != image.channels())
      return Status::Error(path.string() + ": " + std::to_string(options.channel_names.size()) + " channel names for " +
                           std::to_string(image.channels()) + " channels");
    spec.channelnames = options.channel_names;
  }

  // Encode sRGB ourselves so 8-bit output is exactly reproducible.
  std::vector<uint8_t> bytes;  // 8-bit encodings made here
  const void* pixels = image.data();
  oiio::TypeDesc pixel_type = oiio::TypeDesc::FLOAT;
  if (options.format == PixelFormat::kUint8Srgb) {
    bytes.resize(image.size());
    const float* src = image.data();
    for (size_t i = 0; i < bytes.size(); ++i) bytes[i] = EncodeSrgb8(src[i]);
    pixels = bytes.data();
    pixel_type = oiio::TypeDesc::UINT8;
  } else if (options.format == PixelFormat::kUint8Linear) {
    bytes.resize(image.size());
    const float* src = image.data();
    for (size_t i = 0; i < bytes.size(); ++i) bytes[i] = uint8_t(std::lround(std::clamp(src[i], 0.0f, 1.0f) * 255.0f));
    pixels = bytes.data();
    pixel_type = oiio::TypeDesc::UINT8;
  }

  return WriteFileAtomically(path, [&](const fs::path& temp) -> Status {
    auto out = oiio::ImageOutput::create(path.string());
    if (!out) return Status::Error(path.string() + ": no image writer for this extension");
    if (!out->open(temp.string(), spec))
      return Status::Error(path.string() + ": " + out->geterror());
    const bool wrote = out->write_image(pixel_type, pixels);
    const std::string err = out->geterror();
    if (!out->close() || !wrote) return Status::Error(path.string() + ": " + err);
    return Status::Ok();
  });
}

}  // namespace mesocap
