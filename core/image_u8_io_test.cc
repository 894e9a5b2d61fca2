#include "core/image_u8_io.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <random>
#include <vector>

#include "core/image_io.h"
#include "tests/testing.h"

namespace mesocap {
namespace {

// Texture with edges and noise, so the JPEG has non-trivial AC coefficients and chroma.
Image Textured(int w, int h, int c, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> noise(-0.1f, 0.1f);
  Image im(w, h, c);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int k = 0; k < c; ++k) {
        const float v = 0.5f + 0.3f * std::sin(0.21f * x + 1.3f * k) * std::cos(0.17f * y) +
                        ((x / 9 + y / 7 + k) % 2 ? 0.1f : -0.1f) + noise(rng);
        im.at(x, y, k) = std::clamp(v, 0.0f, 1.0f);
      }
  return im;
}

// Largest |u8 - 255 * float| between the fast reader and OpenImageIO's float decode.
int MaxLevelDifference(const ImageU8& u8, const Image& f) {
  EXPECT_EQ(u8.width(), f.width());
  EXPECT_EQ(u8.height(), f.height());
  EXPECT_EQ(u8.channels(), f.channels());
  int worst = 0;
  for (size_t i = 0; i < u8.size() && i < f.size(); ++i)
    worst = std::max(worst, int(std::lround(std::abs(u8.data()[i] - 255.0f * f.data()[i]))));
  return worst;
}

TEST(ImageU8IO, JpegMatchesOpenImageIODecodeWithinOneLevel) {
  const auto dir = testing::MakeTempDir();
  const uint32_t seed = testing::SeedFromTestName();
  // Odd sizes exercise partial MCUs; 3 channels are stored as subsampled YCbCr, 1 as grey.
  for (int channels : {3, 1}) {
    const auto path = dir / (channels == 3 ? "t3.jpg" : "t1.jpg");
    ImageWriteOptions jpeg;
    jpeg.jpeg_quality = 90;
    ASSERT_TRUE(WriteImage(path, Textured(77, 45, channels, seed), jpeg).ok());
    auto fast = ReadImageU8(path);
    ASSERT_TRUE(fast.ok()) << fast.status().message();
    auto oiio = ReadImage(path, {.linearize = false});
    ASSERT_TRUE(oiio.ok()) << oiio.status().message();
    EXPECT_LE(MaxLevelDifference(*fast, *oiio), 1) << channels << " channels";
    EXPECT_TRUE(ImageU8ToFloat(*fast).width() == 77);
  }
  // A colour JPEG read with max_channels 1 comes out grey.
  auto grey = ReadImageU8(dir / "t3.jpg", 1);
  ASSERT_TRUE(grey.ok()) << grey.status().message();
  EXPECT_EQ(grey->channels(), 1);
}

TEST(ImageU8IO, OtherEightBitFormatsGoThroughOpenImageIO) {
  const auto dir = testing::MakeTempDir();
  const Image im = Textured(31, 17, 4, testing::SeedFromTestName());
  ImageWriteOptions png8, png16;
  png8.format = PixelFormat::kUint8Srgb;
  png16.format = PixelFormat::kUint16Linear;
  ASSERT_TRUE(WriteImage(dir / "a.png", im, png8).ok());
  auto fast = ReadImageU8(dir / "a.png", 3);
  ASSERT_TRUE(fast.ok()) << fast.status().message();
  EXPECT_EQ(fast->channels(), 3);
  auto oiio = ReadImage(dir / "a.png", {.linearize = false, .max_channels = 3});
  ASSERT_TRUE(oiio.ok());
  EXPECT_EQ(MaxLevelDifference(*fast, *oiio), 0);
  // 16-bit files are not silently quantised.
  ASSERT_TRUE(WriteImage(dir / "b.png", im, png16).ok());
  auto wide = ReadImageU8(dir / "b.png");
  ASSERT_FALSE(wide.ok());
  EXPECT_NE(wide.status().message().find("b.png"), std::string::npos);
  EXPECT_NE(wide.status().message().find("not an 8-bit image"), std::string::npos)
      << wide.status().message();
}

TEST(ImageU8IO, TruncatedEmptyAndTextFilesAreErrorsNamingTheFile) {
  const auto dir = testing::MakeTempDir();
  ASSERT_TRUE(WriteImage(dir / "good.jpg", Textured(200, 160, 3, 7)).ok());
  const auto size = std::filesystem::file_size(dir / "good.jpg");
  for (double keep : {0.5, 0.95}) {
    const std::string name = keep < 0.9 ? "cut50.jpg" : "cut95.jpg";
    std::filesystem::copy_file(dir / "good.jpg", dir / name);
    std::filesystem::resize_file(dir / name, std::uintmax_t(size * keep));
  }
  // Only the header: fails before any pixel is decoded.
  std::filesystem::copy_file(dir / "good.jpg", dir / "header.jpg");
  std::filesystem::resize_file(dir / "header.jpg", 40);
  std::ofstream(dir / "empty.jpg").close();
  std::ofstream(dir / "notes.jpg") << "not an image at all\n";
  {
    std::ofstream junk(dir / "junk.jpg", std::ios::binary);  // JPEG magic, then garbage
    junk << "\xFF\xD8\xFF\xE0" << std::string(500, '\x5A');
  }
  ASSERT_TRUE(ReadImageU8(dir / "good.jpg").ok());
  for (const char* name :
       {"cut50.jpg", "cut95.jpg", "header.jpg", "empty.jpg", "notes.jpg", "junk.jpg", "missing.jpg"}) {
    auto r = ReadImageU8(dir / name);
    ASSERT_FALSE(r.ok()) << name;
    EXPECT_NE(r.status().message().find(name), std::string::npos) << r.status().message();
  }
}

// Bands of rows, of any size, give the bytes of the whole image; a truncated file fails in the
// band its data runs out, naming the file; a file that is not a JPEG gives no reader.
TEST(ImageU8IO, JpegRowReaderDecodesBandsAsTheWholeImage) {
  const auto dir = testing::MakeTempDir();
  ASSERT_TRUE(WriteImage(dir / "photo.jpg", Textured(83, 71, 3, testing::SeedFromTestName())).ok());
  auto whole = ReadImageU8(dir / "photo.jpg");
  ASSERT_TRUE(whole.ok());
  for (int band : {1, 7, 16, 71}) {
    auto reader = JpegRowReader::Open(dir / "photo.jpg", 3);
    ASSERT_TRUE(reader.ok() && *reader) << reader.status().message();
    JpegRowReader& jpeg = **reader;
    ASSERT_EQ(jpeg.width(), 83);
    ASSERT_EQ(jpeg.height(), 71);
    ASSERT_EQ(jpeg.channels(), 3);
    ImageU8 banded(83, 71, 3);
    for (int y = 0; y < 71; y += band) {
      std::vector<uint8_t*> rows;
      for (int r = y; r < std::min(71, y + band); ++r) rows.push_back(banded.row(r));
      ASSERT_TRUE(jpeg.ReadRows(int(rows.size()), rows.data()).ok());
    }
    EXPECT_TRUE(banded == *whole) << "band of " << band;
  }
  const auto bytes = std::filesystem::file_size(dir / "photo.jpg");
  std::filesystem::copy_file(dir / "photo.jpg", dir / "cut.jpg");
  std::filesystem::resize_file(dir / "cut.jpg", bytes * 2 / 3);
  auto cut = JpegRowReader::Open(dir / "cut.jpg", 3);
  ASSERT_TRUE(cut.ok() && *cut);
  ImageU8 rows_out(83, 71, 3);
  Status last = Status::Ok();
  for (int y = 0; y < 71 && last.ok(); ++y) {
    uint8_t* row = rows_out.row(y);
    last = (*cut)->ReadRows(1, &row);
  }
  EXPECT_FALSE(last.ok());
  EXPECT_NE(last.message().find("cut.jpg"), std::string::npos) << last.message();
  ASSERT_TRUE(WriteImage(dir / "flat.png", Textured(8, 8, 3, 1)).ok());
  auto png = JpegRowReader::Open(dir / "flat.png", 3);
  ASSERT_TRUE(png.ok());
  EXPECT_EQ(png->get(), nullptr);
}

// A progressive JPEG holds the same quantised coefficients as the sequential one, in another
// order: the same bytes when read; a reader for sequential files only gives none for it.
TEST(ImageU8IO, AProgressiveJpegReadsAsTheSequentialOneAndIsRefusedWhenOnlySequentialIsAsked) {
  const auto dir = testing::MakeTempDir();
  const Image picture = Textured(83, 71, 3, testing::SeedFromTestName());
  ImageWriteOptions progressive;
  progressive.attributes["jpeg:progressive"] = 1;
  ASSERT_TRUE(WriteImage(dir / "sequential.jpg", picture).ok());
  ASSERT_TRUE(WriteImage(dir / "progressive.jpg", picture, progressive).ok());
  auto expected = ReadImageU8(dir / "sequential.jpg");
  ASSERT_TRUE(expected.ok());
  auto any = JpegRowReader::Open(dir / "progressive.jpg", 3);
  ASSERT_TRUE(any.ok() && *any) << any.status().message();
  auto decoded = (*any)->ReadAll();
  ASSERT_TRUE(decoded.ok());
  EXPECT_TRUE(*decoded == *expected);
  auto sequential_only = JpegRowReader::Open(dir / "progressive.jpg", 3, 0, JpegRowReader::Scans::kSequentialOnly);
  ASSERT_TRUE(sequential_only.ok());
  EXPECT_EQ(sequential_only->get(), nullptr);
  auto sequential = JpegRowReader::Open(dir / "sequential.jpg", 3, 0, JpegRowReader::Scans::kSequentialOnly);
  ASSERT_TRUE(sequential.ok() && *sequential);
}

TEST(ImageU8IO, JpegRowReaderTellsWhetherColourIsKeptAtALowerResolution) {
  const auto dir = testing::MakeTempDir();
  ImageWriteOptions subsampled, full;
  subsampled.attributes["jpeg:subsampling"] = std::string("4:2:0");
  full.attributes["jpeg:subsampling"] = std::string("4:4:4");
  ASSERT_TRUE(WriteImage(dir / "420.jpg", Textured(64, 48, 3, 1), subsampled).ok());
  ASSERT_TRUE(WriteImage(dir / "444.jpg", Textured(64, 48, 3, 1), full).ok());
  ASSERT_TRUE(WriteImage(dir / "grey.jpg", Textured(64, 48, 1, 1), subsampled).ok());
  for (const auto& [name, expected] : {std::pair{"420.jpg", true}, {"444.jpg", false}, {"grey.jpg", false}}) {
    auto reader = JpegRowReader::Open(dir / name);
    ASSERT_TRUE(reader.ok() && *reader) << name;
    EXPECT_EQ((*reader)->chroma_subsampled(), expected) << name;
  }
}

// Decoding at 1/2, 1/4 and 1/8 of the size gives about the block averages of the full decode
// (libjpeg's scaled IDCT keeps each 8x8 block's low frequencies).
TEST(ImageU8IO, JpegRowReaderDecodesAtAFractionOfTheSize) {
  const auto dir = testing::MakeTempDir();
  ASSERT_TRUE(WriteImage(dir / "photo.jpg", Textured(256, 192, 3, testing::SeedFromTestName())).ok());
  auto whole = ReadImageU8(dir / "photo.jpg");
  ASSERT_TRUE(whole.ok());
  // The smallest reduction that keeps `min_width`: one pixel more asks for the next size up.
  for (const auto& [min_width, expected] : {std::pair{0, 1}, {129, 1}, {65, 2}, {33, 4}, {32, 8}, {1, 8}}) {
    auto reader = JpegRowReader::Open(dir / "photo.jpg", 3, min_width);
    ASSERT_TRUE(reader.ok() && *reader) << reader.status().message();
    EXPECT_EQ((*reader)->width(), 256 / expected) << "min_width " << min_width;
    EXPECT_EQ((*reader)->height(), 192 / expected) << "min_width " << min_width;
  }
  for (int reduce : {2, 4, 8}) {
    auto reader = JpegRowReader::Open(dir / "photo.jpg", 3, 256 / reduce);
    ASSERT_TRUE(reader.ok() && *reader) << reader.status().message();
    auto read = (*reader)->ReadAll();
    ASSERT_TRUE(read.ok()) << read.status().message();
    const ImageU8& small = *read;
    ASSERT_EQ(small.width(), 256 / reduce);
    ASSERT_EQ(small.height(), 192 / reduce);
    double worst = 0, sum = 0;
    for (int y = 0; y < small.height(); ++y)
      for (int x = 0; x < small.width(); ++x)
        for (int c = 0; c < 3; ++c) {
          double mean = 0;
          for (int j = 0; j < reduce; ++j)
            for (int i = 0; i < reduce; ++i) mean += whole->row(y * reduce + j)[(x * reduce + i) * 3 + c];
          mean /= reduce * reduce;
          const double d = std::abs(small.row(y)[x * 3 + c] - mean);
          worst = std::max(worst, d), sum += d;
        }
    // Measured: mean 4.0, 2.0, 1.0 levels; worst 30, 15, 6 (the texture's per-pixel noise is what
    // the scaled transform and the box average treat differently).
    EXPECT_LT(sum / small.size(), 10.0 / reduce) << "reduce " << reduce;
    EXPECT_LT(worst, 60.0 / reduce) << "reduce " << reduce;
  }
}

TEST(ImageU8IO, CopyAndCompare) {
  ImageU8 a(3, 2, 3);
  for (size_t i = 0; i < a.size(); ++i) a.data()[i] = uint8_t(i * 11);
  ImageU8 b = a;
  EXPECT_TRUE(a == b);
  b.at(2, 1, 2) = 1;
  EXPECT_FALSE(a == b);
  const Image f = ImageU8ToFloat(a);
  EXPECT_EQ(f.at(1, 0, 0), float(a.at(1, 0, 0)) * kU8ToUnit);
  EXPECT_FLOAT_EQ(f.at(2, 1, 2), float(a.at(2, 1, 2)) / 255.0f);
}

}  // namespace
}  // namespace mesocap
