#include "core/image_u8_io.h"

#include <algorithm>
#include <csetjmp>
#include <cstdlib>
#include <new>
#include <cstdio>
#include <cstring>
#include <string>

#include "core/image_io.h"
#include "core/image_codec.h"

#ifdef __linux__
#include <sys/mman.h>
#endif

// jpeglib.h needs size_t and FILE declared first.
#include <jpeglib.h>

namespace mesocap {
namespace fs = std::filesystem;

namespace {

uint8_t* AllocatePixels(size_t bytes) {
#ifdef __linux__
  constexpr size_t kHugePage = size_t(2) << 20;
  if (bytes >= kHugePage) {
    const size_t rounded = (bytes + kHugePage - 1) / kHugePage * kHugePage;
    if (void* p = std::aligned_alloc(kHugePage, rounded)) {
      madvise(p, rounded, MADV_HUGEPAGE);  // a hint: failure only costs speed
      return static_cast<uint8_t*>(p);
    }
  }
#endif
  void* p = std::malloc(std::max<size_t>(bytes, 1));
  if (!p) throw std::bad_alloc();
  return static_cast<uint8_t*>(p);
}

}  // namespace

void ImageU8::Free::operator()(uint8_t* p) const { std::free(p); }

ImageU8::ImageU8(int width, int height, int channels)
    : width_(width), height_(height), channels_(channels) {
  MESOCAP_CHECK(width > 0 && height > 0 && channels > 0, "ImageU8 needs a positive size");
  data_.reset(AllocatePixels(size()));  // not zeroed
}

ImageU8::ImageU8(const ImageU8& other)
    : width_(other.width_), height_(other.height_), channels_(other.channels_) {
  if (other.data_) {
    data_.reset(AllocatePixels(size()));
    std::memcpy(data_.get(), other.data_.get(), size());
  }
}

ImageU8& ImageU8::operator=(const ImageU8& other) {
  if (this != &other) *this = ImageU8(other);
  return *this;
}

bool ImageU8::operator==(const ImageU8& other) const {
  if (width_ != other.width_ || height_ != other.height_ || channels_ != other.channels_)
    return false;
  return size() == 0 || std::memcmp(data(), other.data(), size()) == 0;
}

Image ImageU8ToFloat(const ImageU8& image) {
  if (image.empty()) return Image();
  Image out(image.width(), image.height(), image.channels());
  const uint8_t* src = image.data();
  float* dst = out.data();
  for (size_t i = 0; i < image.size(); ++i) dst[i] = float(src[i]) * kU8ToUnit;
  return out;
}

namespace {

// libjpeg reports errors through callbacks: keep the message and jump back to the decoder.
struct JpegErrorManager {
  jpeg_error_mgr base;
  std::jmp_buf jump;
  char message[JMSG_LENGTH_MAX];
};

[[noreturn]] void JpegErrorExit(j_common_ptr cinfo) {
  auto* err = reinterpret_cast<JpegErrorManager*>(cinfo->err);
  (*cinfo->err->format_message)(cinfo, err->message);
  std::longjmp(err->jump, 1);
}

// Warnings (level -1) mean corrupt data that libjpeg papers over, e.g. a truncated file padded
// with grey: fail as OpenImageIO-based ReadImage does. Trace messages (level >= 0) are ignored.
void JpegEmitMessage(j_common_ptr cinfo, int level) {
  if (level < 0) JpegErrorExit(cinfo);
}

enum class JpegResult { kOk, kError, kUnsupported, kTooLarge };

// Decodes a JPEG held in memory into *out. Kept free of objects with destructors between
// setjmp and the calls that may longjmp; *out and *error belong to the caller.
JpegResult DecodeJpeg(const uint8_t* bytes, size_t size, int max_channels, ImageU8* out,
                      std::string* error, int64_t* width, int64_t* height) {
  jpeg_decompress_struct cinfo;
  JpegErrorManager err;
  cinfo.err = jpeg_std_error(&err.base);
  err.base.error_exit = JpegErrorExit;
  err.base.emit_message = JpegEmitMessage;
  err.message[0] = '\0';
  if (setjmp(err.jump)) {
    jpeg_destroy_decompress(&cinfo);
    *error = err.message;
    return JpegResult::kError;
  }
  jpeg_create_decompress(&cinfo);
  jpeg_mem_src(&cinfo, bytes, static_cast<unsigned long>(size));
  jpeg_read_header(&cinfo, TRUE);
  // The one size rule of every reader (CheckImageSize), before a byte of pixels is allocated.
  if (!CheckImageSize("", cinfo.image_width, cinfo.image_height, cinfo.num_components).ok()) {
    *width = cinfo.image_width, *height = cinfo.image_height;
    jpeg_destroy_decompress(&cinfo);
    return JpegResult::kTooLarge;
  }
  if (cinfo.data_precision != 8 || (cinfo.jpeg_color_space != JCS_GRAYSCALE &&
                                    cinfo.jpeg_color_space != JCS_YCbCr &&
                                    cinfo.jpeg_color_space != JCS_RGB)) {
    jpeg_destroy_decompress(&cinfo);  // CMYK/YCCK or 12-bit: leave it to OpenImageIO
    return JpegResult::kUnsupported;
  }
  const bool grey = cinfo.jpeg_color_space == JCS_GRAYSCALE || max_channels < 3;
  cinfo.out_color_space = grey ? JCS_GRAYSCALE : JCS_RGB;
  cinfo.dct_method = JDCT_ISLOW;  // accurate (and SIMD in libjpeg-turbo); not JDCT_IFAST
  jpeg_start_decompress(&cinfo);
  *out = ImageU8(int(cinfo.output_width), int(cinfo.output_height), cinfo.output_components);
  JSAMPROW rows[16];
  while (cinfo.output_scanline < cinfo.output_height) {
    const int first = int(cinfo.output_scanline);
    const int count = std::min<int>(16, int(cinfo.output_height) - first);
    for (int r = 0; r < count; ++r) rows[r] = out->row(first + r);
    jpeg_read_scanlines(&cinfo, rows, JDIMENSION(count));
  }
  jpeg_finish_decompress(&cinfo);
  jpeg_destroy_decompress(&cinfo);
  return JpegResult::kOk;
}

// The declared size of a JPEG (a file starting with the SOI marker FF D8), read by libjpeg from
// the file up to its frame header, nothing more; Ok for other files and for headers too broken
// to read (the decoder reports those).
Status CheckJpegDeclaredSizeImpl(const fs::path& path, std::FILE* file) {
  jpeg_decompress_struct cinfo;
  JpegErrorManager err;
  cinfo.err = jpeg_std_error(&err.base);
  err.base.error_exit = JpegErrorExit;  // warnings keep their default: only the size matters here
  if (setjmp(err.jump)) {
    jpeg_destroy_decompress(&cinfo);
    return Status::Ok();
  }
  jpeg_create_decompress(&cinfo);
  jpeg_stdio_src(&cinfo, file);
  jpeg_read_header(&cinfo, TRUE);
  const int64_t width = cinfo.image_width, height = cinfo.image_height, components = cinfo.num_components;
  jpeg_destroy_decompress(&cinfo);
  return CheckImageSize(path, width, height, components);
}

// Formats other than baseline 8-bit JPEG, through the image codec (core/image_codec.h).
StatusOr<ImageU8> ReadWithCodec(const fs::path& path, int max_channels) {
  if (Status size = CheckDeclaredImageSize(path); !size.ok()) return size;
  auto codec = LoadImageCodec();
  if (!codec.ok()) return codec.status();
  ImageU8 image;
  auto target = [&](const ImageInfo& header) -> StatusOr<DecodeTarget> {
    if (header.channels <= 0) return Status::Error(path.string() + ": image has no pixels");
    if (Status size = CheckImageSize(path, header.width, header.height, header.channels); !size.ok()) return size;
    if (!header.stored_as_uint8 || header.bits_per_sample != 8)
      return Status::Error(path.string() + ": not an 8-bit image (" + std::to_string(header.bits_per_sample) +
                           " bits per sample); read it as float instead");
    const int channels = std::min(header.channels, max_channels);
    image = ImageU8(header.width, header.height, channels);
    return DecodeTarget{image.data(), SampleType::kUint8, channels};
  };
  MESOCAP_RETURN_IF_ERROR((*codec)->Read(path, 0, target));
  return image;
}

}  // namespace

Status CheckJpegDeclaredSize(const fs::path& path) {
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (!file) return Status::Ok();  // the reader reports it
  unsigned char soi[2] = {0, 0};
  const bool is_jpeg = std::fread(soi, 1, 2, file) == 2 && soi[0] == 0xFF && soi[1] == 0xD8;
  std::rewind(file);
  Status status = is_jpeg ? CheckJpegDeclaredSizeImpl(path, file) : Status::Ok();
  std::fclose(file);
  return status;
}

StatusOr<ImageU8> ReadImageU8(const fs::path& path, int max_channels) {
  MESOCAP_CHECK(max_channels >= 1, "max_channels must be at least 1");
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return Status::Error(path.string() + ": no such file");
  const auto file_size = fs::file_size(path, ec);
  if (ec) return Status::Error(path.string() + ": " + ec.message());
  if (file_size == 0) return Status::Error(path.string() + ": empty file");
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (!file) return Status::Error(path.string() + ": cannot open: " + std::strerror(errno));
  std::unique_ptr<uint8_t[]> bytes(new uint8_t[file_size]);
  const size_t got = std::fread(bytes.get(), 1, file_size, file);
  std::fclose(file);
  if (got != file_size) return Status::Error(path.string() + ": read error");

  const bool is_jpeg = file_size >= 3 && bytes[0] == 0xFF && bytes[1] == 0xD8 && bytes[2] == 0xFF;
  if (is_jpeg) {
    ImageU8 image;
    std::string error;
    int64_t width = 0, height = 0;
    switch (DecodeJpeg(bytes.get(), file_size, max_channels, &image, &error, &width, &height)) {
      case JpegResult::kOk:
        return image;
      case JpegResult::kTooLarge:
        return CheckImageSize(path, width, height);
      case JpegResult::kError:
        return Status::Error(path.string() + ": " + (error.empty() ? "corrupt JPEG" : error));
      case JpegResult::kUnsupported:
        break;
    }
  }
  bytes.reset();
  return ReadWithCodec(path, max_channels);
}

}  // namespace mesocap
