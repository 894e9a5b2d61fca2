#include "core/image_io.h"

#include <gtest/gtest.h>

#include <fstream>

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

}  // namespace
}  // namespace mesocap
