#include "core/image_io.h"

#include <gtest/gtest.h>

#include <fstream>
#include <limits>

#include "core/image_u8_io.h"

#include "tests/testing.h"

namespace mesocap {
namespace {

Image Ramp(int w, int h, int c) {
  Image im(w, h, c);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int k = 0; k < c; ++k) im.at(x, y, k) = float(x + 2 * y + k) / float(w + 2 * h + c);
  return im;
}

TEST(ImageIO, ExrFloatRoundTripIsExactAndKeepsAttributes) {
  const auto dir = testing::MakeTempDir();
  const Image im = Ramp(37, 21, 3);
  ImageWriteOptions opt;
  opt.format = PixelFormat::kFloat;
  opt.attributes["mesocap:theta_i_deg"] = 30.5f;
  opt.attributes["mesocap:material"] = std::string("weave");
  ASSERT_TRUE(WriteImage(dir / "a.exr", im, opt).ok());
  ImageInfo info;
  auto back = ReadImage(dir / "a.exr", {}, &info);
  ASSERT_TRUE(back.ok()) << back.status().message();
  EXPECT_EQ(*back, im);
  EXPECT_FLOAT_EQ(std::get<float>(info.attributes.at("mesocap:theta_i_deg")), 30.5f);
  EXPECT_EQ(std::get<std::string>(info.attributes.at("mesocap:material")), "weave");
}

TEST(ImageIO, AnExrAskedForInEightBitsIsRefusedNotSrgbEncoded) {
  const auto dir = testing::MakeTempDir();
  const Image im(4, 3, 3, 0.032f);
  const Status st = WriteImage(dir / "slice.exr", im);  // the default options: 8-bit sRGB
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.message().find("slice.exr"), std::string::npos) << st.message();
  EXPECT_FALSE(std::filesystem::exists(dir / "slice.exr"));
  ASSERT_TRUE(WriteImage(dir / "slice.exr", im, {.format = PixelFormat::kHalf}).ok());
  auto back = ReadImage(dir / "slice.exr");
  ASSERT_TRUE(back.ok());
  EXPECT_NEAR(back->at(3, 2, 1), 0.032f, 1e-4f);
}

TEST(ImageIO, Png16IsLinearAndJpegIsSrgbWithinQuantisation) {
  const auto dir = testing::MakeTempDir();
  const Image im = Ramp(64, 32, 3);
  ASSERT_TRUE(WriteImage(dir / "a.png", im, {.format = PixelFormat::kUint16Linear}).ok());
  auto png = ReadImage(dir / "a.png");
  ASSERT_TRUE(png.ok());
  for (size_t i = 0; i < im.size(); ++i) EXPECT_NEAR(png->data()[i], im.data()[i], 1.0 / 65535);
  ASSERT_TRUE(WriteImage(dir / "a.jpg", im, {.format = PixelFormat::kUint8Srgb, .jpeg_quality = 100}).ok());
  auto jpg = ReadImage(dir / "a.jpg");
  ASSERT_TRUE(jpg.ok());
  // sRGB decoding makes the values linear again; JPEG adds a little error.
  double err = 0;
  for (size_t i = 0; i < im.size(); ++i) err += std::abs(jpg->data()[i] - im.data()[i]);
  EXPECT_LT(err / im.size(), 0.01);
}

TEST(ImageIO, TruncatedEmptyAndTextFilesAreErrorsNamingTheFile) {
  const auto dir = testing::MakeTempDir();
  ASSERT_TRUE(WriteImage(dir / "good.jpg", Ramp(200, 200, 3)).ok());
  const auto size = std::filesystem::file_size(dir / "good.jpg");
  std::filesystem::copy_file(dir / "good.jpg", dir / "cut.jpg");
  std::filesystem::resize_file(dir / "cut.jpg", size / 2);
  std::ofstream(dir / "empty.jpg").close();
  std::ofstream(dir / "notes.jpg") << "not an image at all\n";
  for (const char* name : {"cut.jpg", "empty.jpg", "notes.jpg", "missing.jpg"}) {
    auto r = ReadImage(dir / name);
    ASSERT_FALSE(r.ok()) << name;
    EXPECT_NE(r.status().message().find(name), std::string::npos) << r.status().message();
  }
}

TEST(ImageIO, MatBridgeSharesMemory) {
  Image im(4, 3, 2);
  cv::Mat m = im.AsMat();
  m.at<cv::Vec2f>(1, 2)[1] = 7.0f;
  EXPECT_EQ(im.at(2, 1, 1), 7.0f);
  const Image copy = Image::FromMat(m);
  EXPECT_EQ(copy, im);
}


std::string FileBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), {});
}

// Overwrites the int32 that follows `key` (an attribute's name\0type\0) in `bytes`.
void PatchInt32After(std::string* bytes, const std::string& key, int32_t value) {
  const size_t at = bytes->find(key);
  ASSERT_NE(at, std::string::npos) << key;
  bytes->replace(at + key.size(), 4, reinterpret_cast<const char*>(&value), 4);
}

// A copy of `exr` beside it, named b.exr, with the int32 after `key` set to `value`.
std::filesystem::path PatchedCopy(const std::filesystem::path& exr, const std::string& key, int32_t value) {
  std::string bytes = FileBytes(exr);
  PatchInt32After(&bytes, key, value);
  const auto copy = exr.parent_path() / "b.exr";
  std::ofstream(copy, std::ios::binary) << bytes;
  return copy;
}

// A small valid JPEG whose frame header (SOF0) is rewritten to declare width x height.
std::string JpegDeclaring(const std::filesystem::path& path, int width, int height) {
  EXPECT_TRUE(WriteImage(path, Ramp(16, 16, 3)).ok());
  std::string bytes = FileBytes(path);
  const size_t sof = bytes.find("\xFF\xC0");
  EXPECT_NE(sof, std::string::npos);
  bytes[sof + 5] = char(height >> 8), bytes[sof + 6] = char(height & 255);
  bytes[sof + 7] = char(width >> 8), bytes[sof + 8] = char(width & 255);
  std::ofstream(path, std::ios::binary) << bytes;
  return bytes;
}

TEST(ImageIO, HeadersDeclaringMoreThanTheCapAreRefusedBeforeAllocating) {
  const auto dir = testing::MakeTempDir();
  const auto path = dir / "huge.jpg";
  const std::string bytes = JpegDeclaring(path, 60000, 60000);
  EXPECT_LT(bytes.size(), 2000u);
  auto info = ReadImageInfo(path);
  ASSERT_FALSE(info.ok());
  EXPECT_NE(info.status().message().find("huge.jpg"), std::string::npos) << info.status().message();
  EXPECT_NE(info.status().message().find("60000x60000"), std::string::npos) << info.status().message();
  EXPECT_FALSE(ReadImage(path).ok());
  EXPECT_FALSE(ReadImage(path, {.linearize = false}).ok());
  auto u8 = ReadImageU8(path);
  ASSERT_FALSE(u8.ok());
  EXPECT_NE(u8.status().message().find("megapixels"), std::string::npos) << u8.status().message();
  // The cap is an option: below it the same kind of header is read as usual. (A 16-pixel row
  // needs a cap of 16 x 256 rows, the band decoders buffer.)
  JpegDeclaring(dir / "small.jpg", 16, 16);
  SetMaxImagePixels(16 * 256 - 1);
  EXPECT_FALSE(ReadImageU8(dir / "small.jpg").ok());
  EXPECT_FALSE(ReadImage(dir / "small.jpg").ok());
  SetMaxImagePixels(16 * 256);
  EXPECT_TRUE(ReadImageU8(dir / "small.jpg").ok());
  EXPECT_TRUE(ReadImage(dir / "small.jpg").ok());
  SetMaxImagePixels(kDefaultMaxImagePixels);
}

TEST(ImageIO, EightBitWritingIsTotalOnNanInfinityAndOutOfRange) {
  const auto dir = testing::MakeTempDir();
  Image im(4, 1, 1);
  im.at(0, 0) = std::numeric_limits<float>::quiet_NaN();
  im.at(1, 0) = std::numeric_limits<float>::infinity();
  im.at(2, 0) = -std::numeric_limits<float>::infinity();
  im.at(3, 0) = 1e30f;
  ASSERT_TRUE(WriteImage(dir / "a.png", im, {.format = PixelFormat::kUint8Srgb}).ok());
  auto back = ReadImageU8(dir / "a.png");
  ASSERT_TRUE(back.ok()) << back.status().message();
  EXPECT_EQ(back->at(0, 0), 0);
  EXPECT_EQ(back->at(1, 0), 255);
  EXPECT_EQ(back->at(2, 0), 0);
  EXPECT_EQ(back->at(3, 0), 255);
}

TEST(ImageIO, EveryFormatOpenImageIOReadsCountsAsAnImage) {
  for (const char* name : {"a.jpg", "a.JPEG", "a.png", "a.tif", "a.exr", "a.tga", "a.BMP", "a.cr2", "a.dng"})
    EXPECT_TRUE(HasReadableImageExtension(name)) << name;
  for (const char* name : {"a.txt", "a.json", "a.lp", "a.ptm", "noextension"})
    EXPECT_FALSE(HasReadableImageExtension(name)) << name;
  // And such a file reads: a TGA written by OpenImageIO comes back.
  const auto dir = testing::MakeTempDir();
  ASSERT_TRUE(WriteImage(dir / "a.tga", Ramp(8, 4, 3)).ok());
  EXPECT_TRUE(ReadImage(dir / "a.tga").ok());
}

TEST(ImageIO, OnlyTheReaderForTheExtensionOpensAFile) {
  // OpenImageIO's open() tries every reader it has when the named one fails; fuzz_image_u8 found
  // one of them (RLA) aborting the process on a corrupt .jpg. A file must match its extension.
  const auto dir = testing::MakeTempDir();
  ASSERT_TRUE(WriteImage(dir / "a.png", Ramp(8, 4, 3)).ok());
  std::filesystem::copy_file(dir / "a.png", dir / "png_named.jpg");
  auto image = ReadImage(dir / "png_named.jpg");
  ASSERT_FALSE(image.ok());
  EXPECT_NE(image.status().message().find("png_named.jpg"), std::string::npos) << image.status().message();
  EXPECT_FALSE(ReadImageU8(dir / "png_named.jpg").ok());
  EXPECT_TRUE(ReadImage(dir / "a.png").ok());
  std::ofstream(dir / "notes.txt") << "not an image";
  auto text = ReadImageInfo(dir / "notes.txt");
  ASSERT_FALSE(text.ok());
  EXPECT_NE(text.status().message().find("not an image"), std::string::npos) << text.status().message();
}

TEST(ImageIO, AnExrAttributeLargerThanTheFileIsRefusedBeforeOpenExrAllocatesIt) {
  // Found by fuzz/fuzz_image: OpenEXR allocated an attribute's declared size (2 GB) first.
  const auto dir = testing::MakeTempDir();
  ASSERT_TRUE(WriteImage(dir / "a.exr", Ramp(8, 4, 3), {.format = PixelFormat::kHalf}).ok());
  PatchedCopy(dir / "a.exr", std::string("channels\0chlist\0", 16), 0x7fffff00);
  auto info = ReadImageInfo(dir / "b.exr");
  ASSERT_FALSE(info.ok());
  EXPECT_NE(info.status().message().find("b.exr: malformed OpenEXR header: attribute 'channels' declares"),
            std::string::npos) << info.status().message();
  EXPECT_FALSE(ReadImageU8(dir / "b.exr").ok());
  EXPECT_TRUE(ReadImageInfo(dir / "a.exr").ok());
}

TEST(ImageIO, EveryExrAttributeIsCheckedNotOnlyThoseBeforeTheDataWindow) {
  // Found by fuzz/fuzz_image: the check stopped at dataWindow; OpenEXR allocates later ones too.
  const auto dir = testing::MakeTempDir();
  ASSERT_TRUE(WriteImage(dir / "a.exr", Ramp(8, 4, 3), {.format = PixelFormat::kHalf}).ok());
  PatchedCopy(dir / "a.exr", std::string("pixelAspectRatio\0float\0", 23), 0x7fffff00);
  auto info = ReadImageInfo(dir / "b.exr");
  ASSERT_FALSE(info.ok());
  EXPECT_NE(info.status().message().find("attribute 'pixelAspectRatio' declares"), std::string::npos)
      << info.status().message();
}

TEST(ImageIO, AnExrAttributeWhoseSizeDisagreesWithItsTypeIsRefused) {
  // Found by fuzz/fuzz_image: an int declaring 168 bytes. OpenEXR reads 4 and parses the rest as
  // further attributes, one of them a 2 GB string; the header walk had skipped all 168.
  const auto dir = testing::MakeTempDir();
  ImageWriteOptions options{.format = PixelFormat::kHalf};
  options.attributes["mesocap:board"] = 3;
  ASSERT_TRUE(WriteImage(dir / "a.exr", Ramp(8, 4, 3), options).ok());
  PatchedCopy(dir / "a.exr", std::string("mesocap:board\0int\0", 18), 168);
  auto info = ReadImageInfo(dir / "b.exr");
  ASSERT_FALSE(info.ok());
  EXPECT_NE(info.status().message().find("attribute 'mesocap:board' of type int declares 168 bytes, not 4"),
            std::string::npos) << info.status().message();
  EXPECT_TRUE(ReadImageInfo(dir / "a.exr").ok());
}

TEST(ImageIO, AnExrChannelOfAnUnknownPixelTypeIsRefused) {
  // Found by fuzz/fuzz_synth_files: OpenImageIO asserts (aborts the process) on pixel type 3.
  const auto dir = testing::MakeTempDir();
  ASSERT_TRUE(WriteImage(dir / "a.exr", Ramp(8, 4, 3), {.format = PixelFormat::kHalf}).ok());
  const std::string bytes = FileBytes(dir / "a.exr");
  // The first channel's pixel type follows the list's declared size and the channel's name "B".
  const std::string list("channels\0chlist\0", 16);
  const size_t at = bytes.find(list);
  ASSERT_NE(at, std::string::npos);
  PatchedCopy(dir / "a.exr", bytes.substr(at, list.size() + 4) + std::string("B\0", 2), 3);
  auto info = ReadImageInfo(dir / "b.exr");
  ASSERT_FALSE(info.ok());
  EXPECT_NE(info.status().message().find("b.exr: malformed OpenEXR header: channel 'B' has pixel type 3"),
            std::string::npos) << info.status().message();
  EXPECT_FALSE(ReadImage(dir / "b.exr").ok());
  EXPECT_TRUE(ReadImageInfo(dir / "a.exr").ok());
}

TEST(ImageIO, AnExrWhoseOffsetTableCannotFitInTheFileIsRefused) {
  // A data window of 1 x 10 million rows is within the pixel cap, but its uncompressed offset
  // table (one 8-byte entry per row) would be 80 MB, allocated before any pixel is read.
  const auto dir = testing::MakeTempDir();
  ASSERT_TRUE(WriteImage(dir / "a.exr", Ramp(1, 4, 1), {.format = PixelFormat::kHalf, .exr_compression = "none"}).ok());
  std::string bytes = FileBytes(dir / "a.exr");
  const std::string key("dataWindow\0box2i\0", 17);
  const size_t at = bytes.find(key);
  ASSERT_NE(at, std::string::npos);
  const int32_t window[4] = {0, 0, 0, 9999999};
  bytes.replace(at + key.size() + 4, 16, reinterpret_cast<const char*>(window), 16);
  std::ofstream(dir / "b.exr", std::ios::binary) << bytes;
  auto info = ReadImageInfo(dir / "b.exr");
  ASSERT_FALSE(info.ok());
  EXPECT_NE(info.status().message().find("b.exr: malformed OpenEXR file: its headers declare 10000000 pixel blocks"),
            std::string::npos) << info.status().message();
  EXPECT_FALSE(ReadImage(dir / "b.exr").ok());
  EXPECT_TRUE(ReadImage(dir / "a.exr").ok());
}

TEST(ImageIO, RowsLongerThanTheCapOver256AreRefused) {
  // Found by fuzz/fuzz_image: a 400-byte EXR declaring 2621444 x 4 pixels (10 MP, within a 16 MP
  // cap) made OpenImageIO allocate 256 rows of it, 2.7 GB. The same holds for an honest file.
  const auto dir = testing::MakeTempDir();
  ASSERT_TRUE(WriteImage(dir / "wide.exr", Ramp(101, 2, 1), {.format = PixelFormat::kFloat}).ok());
  SetMaxImagePixels(256 * 100);
  auto info = ReadImageInfo(dir / "wide.exr");
  ASSERT_FALSE(info.ok());
  EXPECT_NE(info.status().message().find("rows of 101 pixels"), std::string::npos) << info.status().message();
  EXPECT_FALSE(ReadImageU8(dir / "wide.exr").ok());
  SetMaxImagePixels(256 * 101);
  EXPECT_TRUE(ReadImage(dir / "wide.exr").ok());
  SetMaxImagePixels(kDefaultMaxImagePixels);
}

TEST(ImageIO, ChannelsBeyondFourCountAgainstTheCap) {
  // Decoders buffer every declared channel even when only 4 are kept.
  const auto dir = testing::MakeTempDir();
  const std::vector<std::string> names = {"a", "b", "c", "d", "e", "f", "g", "h"};
  ASSERT_TRUE(WriteImage(dir / "a.exr", Ramp(4, 512, 8), {.format = PixelFormat::kHalf, .channel_names = names}).ok());
  SetMaxImagePixels(4095);  // 2048 pixels of 8 channels weigh as 4096 pixels of 4
  auto info = ReadImageInfo(dir / "a.exr");
  ASSERT_FALSE(info.ok());
  EXPECT_NE(info.status().message().find("4x512 pixels of 8 channels"), std::string::npos) << info.status().message();
  EXPECT_FALSE(ReadImage(dir / "a.exr").ok());
  SetMaxImagePixels(4096);
  EXPECT_TRUE(ReadImage(dir / "a.exr").ok());
  SetMaxImagePixels(kDefaultMaxImagePixels);
}

}  // namespace
}  // namespace mesocap
