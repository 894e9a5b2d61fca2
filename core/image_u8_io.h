// 8-bit images as stored (no linearisation, no float conversion): the fast read path for
// pipelines that work on many 8-bit photos at once (an RTI folder is 36 x 3 MP; as floats that
// is 1.3 GB, as bytes 324 MB). JPEG is decoded with libjpeg(-turbo) straight to interleaved
// bytes (accurate integer IDCT, the same decoder settings OpenImageIO uses, so values match
// ReadImage(..., {.linearize = false}) * 255 within one level); other 8-bit formats go through
// OpenImageIO. Files that are not 8-bit are an error: read them with ReadImage (core/image_io.h).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <vector>

#include "core/image.h"
#include "core/status.h"

namespace mesocap {

// The scale from an 8-bit code to the [0, 1] float value every 8-bit consumer uses (a float
// path fed with ImageU8ToFloat(image) sees exactly the values a u8 path computes with).
inline constexpr float kU8ToUnit = 1.0f / 255.0f;

// uint8, N interleaved channels, row-major, contiguous. Pixels are left uninitialised on
// construction (decoders overwrite every byte; zeroing 9 MB per photo costs measurable time).
class ImageU8 {
 public:
  ImageU8() = default;
  ImageU8(int width, int height, int channels);
  ImageU8(const ImageU8& other);
  ImageU8& operator=(const ImageU8& other);
  ImageU8(ImageU8&&) noexcept = default;
  ImageU8& operator=(ImageU8&&) noexcept = default;

  int width() const { return width_; }
  int height() const { return height_; }
  int channels() const { return channels_; }
  bool empty() const { return data_ == nullptr; }
  size_t pixel_count() const { return size_t(width_) * size_t(height_); }
  size_t size() const { return pixel_count() * size_t(channels_); }

  uint8_t* data() { return data_.get(); }
  const uint8_t* data() const { return data_.get(); }
  uint8_t* row(int y) { return data_.get() + size_t(y) * width_ * channels_; }
  const uint8_t* row(int y) const { return data_.get() + size_t(y) * width_ * channels_; }
  uint8_t* pixel(int x, int y) { return row(y) + size_t(x) * channels_; }
  const uint8_t* pixel(int x, int y) const { return row(y) + size_t(x) * channels_; }
  uint8_t& at(int x, int y, int c = 0) { return pixel(x, y)[c]; }
  uint8_t at(int x, int y, int c = 0) const { return pixel(x, y)[c]; }

  bool operator==(const ImageU8& other) const;

 private:
  struct Free {
    void operator()(uint8_t* p) const;
  };
  int width_ = 0, height_ = 0, channels_ = 0;
  std::unique_ptr<uint8_t[], Free> data_;
};

// Reads an 8-bit image (JPEG, 8-bit PNG/TIFF/...) as stored, keeping at most `max_channels`
// channels (a colour JPEG read with max_channels 1 or 2 is converted to grey). Errors name the
// file and what was wrong: missing, empty, truncated or corrupt data (libjpeg warnings count as
// errors, as in ReadImage), not 8-bit.
StatusOr<ImageU8> ReadImageU8(const std::filesystem::path& path, int max_channels = 4);

// Decodes a baseline 8-bit JPEG (grey, YCbCr or RGB) a band of rows at a time with libjpeg, for
// pipelines that consume rows in order and should not hold whole photos (fit-ptm streams 36
// photos through bands of rows: the fit reads each band while it is in cache, and no photo is
// ever held whole). Holds the file's bytes and libjpeg's state.
class JpegRowReader {
 public:
  // The reader positioned at row 0; null (not an error) for a file that is not such a JPEG (no
  // JPEG markers, CMYK, 12-bit): read it whole with ReadImageU8. A JPEG that is corrupt, too
  // large (CheckImageSize) or unreadable is an error naming the file. `max_channels` < 3 gives
  // grey.
  // `min_width` > 0 decodes at the smallest of 1/1, 1/2, 1/4 or 1/8 of the size that is still at
  // least that wide, by libjpeg's scaled inverse DCT: a preview needs no full decode.
  // `scans` kSequentialOnly gives null for a progressive JPEG too: libjpeg holds such a file's
  // whole coefficient buffer (about 3 bytes a pixel) from the start of decoding, so readers
  // kept open over many photos would hold every photo; read those whole instead.
  enum class Scans { kAny, kSequentialOnly };
  static StatusOr<std::unique_ptr<JpegRowReader>> Open(const std::filesystem::path& path, int max_channels = 4,
                                                       int min_width = 0, Scans scans = Scans::kAny);
  ~JpegRowReader();
  JpegRowReader(const JpegRowReader&) = delete;
  JpegRowReader& operator=(const JpegRowReader&) = delete;

  int width() const { return width_; }
  int height() const { return height_; }
  int channels() const { return channels_; }
  int next_row() const { return next_row_; }
  // True when the file keeps its colour (Cb, Cr) at a lower resolution than its brightness
  // (4:2:0, 4:2:2 ... as cameras write JPEGs).
  bool chroma_subsampled() const { return chroma_subsampled_; }
  // How many luma samples share one chroma sample across and down: {2, 2} for 4:2:0, {2, 1} for
  // 4:2:2, {1, 1} when the colour is at full resolution (or the image is grey).
  std::array<int, 2> chroma_factors() const { return chroma_factors_; }
  // Decodes the next `count` rows into rows[0..count), each width() * channels() bytes. Corrupt
  // data (libjpeg's warnings included, as in ReadImage) is an error naming the file.
  Status ReadRows(int count, uint8_t* const* rows);
  // Decodes every row (on a reader positioned at row 0) into one image.
  StatusOr<ImageU8> ReadAll();

 private:
  struct Decoder;
  explicit JpegRowReader(std::filesystem::path path);
  std::filesystem::path path_;
  std::unique_ptr<Decoder> decoder_;
  int width_ = 0, height_ = 0, channels_ = 0, next_row_ = 0;
  bool chroma_subsampled_ = false;
  std::array<int, 2> chroma_factors_ = {1, 1};
};

// For a file starting with a JPEG's SOI marker: CheckImageSize on the frame header libjpeg
// finds, before any decoder opens it (libjpeg inside OpenImageIO allocates a progressive JPEG's
// whole coefficient buffer while opening, and tolerates junk after the marker). Ok otherwise.
Status CheckJpegDeclaredSize(const std::filesystem::path& path);

// Values v * kU8ToUnit in a float image of the same shape.
Image ImageU8ToFloat(const ImageU8& image);

}  // namespace mesocap
