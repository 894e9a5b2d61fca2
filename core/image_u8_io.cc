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

// jpeglib.h needs size_t and FILE declared first.
#include <jpeglib.h>

namespace mesocap {
namespace fs = std::filesystem;

void ImageU8::Free::operator()(uint8_t* p) const { FreePixelMemory(p); }

ImageU8::ImageU8(int width, int height, int channels)
    : width_(width), height_(height), channels_(channels) {
  MESOCAP_CHECK(width > 0 && height > 0 && channels > 0, "ImageU8 needs a positive size");
  data_.reset(static_cast<uint8_t*>(AllocatePixelMemory(size())));  // not zeroed
}

ImageU8::ImageU8(const ImageU8& other)
    : width_(other.width_), height_(other.height_), channels_(other.channels_) {
  if (other.data_) {
    data_.reset(static_cast<uint8_t*>(AllocatePixelMemory(size())));
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
  auto reader = JpegRowReader::Open(path, max_channels);
  if (!reader.ok()) return reader.status();
  if (!*reader) return ReadWithCodec(path, max_channels);
  return (*reader)->ReadAll();
}

// libjpeg's decompressor with its error manager. Every call into libjpeg goes through Guarded,
// whose frame holds the setjmp that libjpeg's errors jump back to.
struct JpegRowReader::Decoder {
  jpeg_decompress_struct cinfo;
  JpegErrorManager err;
  // The file stays open and libjpeg reads it through stdio in 64 KB pieces: a reader holds no
  // copy of the file, so fit-ptm's 36 open decoders take no fresh memory for 36 files' bytes
  // (each fresh page costs a fault, several microseconds on our virtual machines).
  std::FILE* file = nullptr;
  // stdio's buffer: glibc ignores setvbuf's size unless it is given the buffer, and reads 4 KB
  // at a time (8500 read calls for fit-ptm's 36 photos instead of 500).
  std::unique_ptr<char[]> file_buffer;
  bool created = false;

  Decoder() {
    cinfo.err = jpeg_std_error(&err.base);
    err.base.error_exit = JpegErrorExit;
    err.base.emit_message = JpegEmitMessage;
    err.message[0] = '\0';
  }
  ~Decoder() {
    if (created) jpeg_destroy_decompress(&cinfo);
    if (file) std::fclose(file);
  }
  // Runs `calls` (libjpeg calls only, no objects with destructors); false with err.message set
  // when libjpeg reported an error or a warning.
  template <typename Calls>
  bool Guarded(const Calls& calls) {
    if (setjmp(err.jump)) return false;
    calls();
    return true;
  }
};

JpegRowReader::JpegRowReader(fs::path path) : path_(std::move(path)), decoder_(std::make_unique<Decoder>()) {}
JpegRowReader::~JpegRowReader() = default;

StatusOr<std::unique_ptr<JpegRowReader>> JpegRowReader::Open(const fs::path& path, int max_channels, int min_width,
                                                               Scans scans) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return Status::Error(path.string() + ": no such file");
  const auto file_size = fs::file_size(path, ec);
  if (ec) return Status::Error(path.string() + ": " + ec.message());
  if (file_size == 0) return Status::Error(path.string() + ": empty file");
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (!file) return Status::Error(path.string() + ": cannot open: " + std::strerror(errno));
  constexpr size_t kFileBuffer = size_t(64) << 10;
  auto file_buffer = std::make_unique_for_overwrite<char[]>(kFileBuffer);
  std::setvbuf(file, file_buffer.get(), _IOFBF, kFileBuffer);  // before any read; on failure stdio's default
  // The markers first: any other file is left to its reader without being read here too.
  uint8_t magic[3] = {0, 0, 0};
  const bool is_jpeg = std::fread(magic, 1, 3, file) == 3 && magic[0] == 0xFF && magic[1] == 0xD8 && magic[2] == 0xFF;
  if (!is_jpeg) {
    std::fclose(file);
    return std::unique_ptr<JpegRowReader>();
  }
  std::unique_ptr<JpegRowReader> reader(new JpegRowReader(path));
  Decoder& d = *reader->decoder_;
  d.file = file;
  d.file_buffer = std::move(file_buffer);
  if (std::fseek(file, 0, SEEK_SET) != 0)
    return Status::Error(path.string() + ": cannot read: " + std::strerror(errno));

  auto corrupt = [&] { return Status::Error(path.string() + ": " + (d.err.message[0] ? d.err.message : "corrupt JPEG")); };
  if (!d.Guarded([&] {
        jpeg_create_decompress(&d.cinfo);
        d.created = true;
        jpeg_stdio_src(&d.cinfo, file);
        jpeg_read_header(&d.cinfo, TRUE);
      }))
    return corrupt();
  // The one size rule of every reader (CheckImageSize), before a byte of pixels is allocated.
  MESOCAP_RETURN_IF_ERROR(CheckImageSize(path, d.cinfo.image_width, d.cinfo.image_height, d.cinfo.num_components));
  if (d.cinfo.data_precision != 8 || (d.cinfo.jpeg_color_space != JCS_GRAYSCALE && d.cinfo.jpeg_color_space != JCS_YCbCr &&
                                      d.cinfo.jpeg_color_space != JCS_RGB))
    return std::unique_ptr<JpegRowReader>();  // CMYK/YCCK or 12-bit: the image codec's reader
  if (scans == Scans::kSequentialOnly && jpeg_has_multiple_scans(&d.cinfo)) return std::unique_ptr<JpegRowReader>();
  if (d.cinfo.num_components == 3) {
    const jpeg_component_info* c = d.cinfo.comp_info;
    for (int k = 1; k < 3; ++k)
      reader->chroma_subsampled_ |= c[k].h_samp_factor < c[0].h_samp_factor || c[k].v_samp_factor < c[0].v_samp_factor;
    if (c[1].h_samp_factor > 0 && c[1].v_samp_factor > 0)
      reader->chroma_factors_ = {c[0].h_samp_factor / c[1].h_samp_factor, c[0].v_samp_factor / c[1].v_samp_factor};
  }
  const bool grey = d.cinfo.jpeg_color_space == JCS_GRAYSCALE || max_channels < 3;
  d.cinfo.out_color_space = grey ? JCS_GRAYSCALE : JCS_RGB;
  d.cinfo.dct_method = JDCT_ISLOW;  // accurate (and SIMD in libjpeg-turbo); not JDCT_IFAST
  unsigned reduce = 1;
  while (min_width > 0 && reduce < 8 && (d.cinfo.image_width + 2 * reduce - 1) / (2 * reduce) >= unsigned(min_width))
    reduce *= 2;
  d.cinfo.scale_num = 1;
  d.cinfo.scale_denom = reduce;
  if (!d.Guarded([&] { jpeg_start_decompress(&d.cinfo); })) return corrupt();
  reader->width_ = int(d.cinfo.output_width);
  reader->height_ = int(d.cinfo.output_height);
  reader->channels_ = d.cinfo.output_components;
  return reader;
}

StatusOr<ImageU8> JpegRowReader::ReadAll() {
  MESOCAP_CHECK(next_row_ == 0, "JpegRowReader: ReadAll on a reader that has read rows");
  ImageU8 image(width_, height_, channels_);
  std::vector<uint8_t*> rows(static_cast<size_t>(height_));
  for (int y = 0; y < height_; ++y) rows[size_t(y)] = image.row(y);
  MESOCAP_RETURN_IF_ERROR(ReadRows(height_, rows.data()));
  return image;
}

Status JpegRowReader::ReadRows(int count, uint8_t* const* rows) {
  MESOCAP_CHECK(count >= 0 && next_row_ + count <= height_, "JpegRowReader: reading past the last row");
  Decoder& d = *decoder_;
  const bool ok = d.Guarded([&] {
    for (int done = 0; done < count;)
      done += int(jpeg_read_scanlines(&d.cinfo, const_cast<JSAMPARRAY>(rows + done), JDIMENSION(count - done)));
    if (int(d.cinfo.output_scanline) == height_) jpeg_finish_decompress(&d.cinfo);
  });
  if (!ok) return Status::Error(path_.string() + ": " + (d.err.message[0] ? d.err.message : "corrupt JPEG"));
  next_row_ += count;
  return Status::Ok();
}

}  // namespace mesocap
