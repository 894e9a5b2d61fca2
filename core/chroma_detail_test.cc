#include "core/chroma_detail.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "core/image_io.h"
#include "tests/testing.h"

namespace mesocap {
namespace {

// A dark red and a light blue mixed in a pattern of periods from 3 to 8 pixels (as a weave's
// threads are in a photo), with a slow shading: the colour contrast a 4:2:0 JPEG blurs. (Colours
// of equal brightness leave the luma nothing to restore them from.)
Image TwoColourDetail(int width, int height) {
  const float a[3] = {0.40f, 0.06f, 0.04f}, b[3] = {0.35f, 0.55f, 0.75f};
  Image im(width, height, 3);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const float mix = std::clamp(0.5f + 0.3f * std::sin(0.9f * x) * std::sin(0.8f * y) + 0.2f * std::sin(2.1f * x + 0.5f * y), 0.0f, 1.0f);
      const float shade = 0.7f + 0.3f * std::cos(0.05f * x + 0.04f * y);
      for (int c = 0; c < 3; ++c) im.at(x, y, c) = shade * (mix * a[c] + (1 - mix) * b[c]);
    }
  return im;
}

StatusOr<std::unique_ptr<JpegRowReader>> WriteJpeg(const std::filesystem::path& path, const Image& image) {
  ImageWriteOptions jpeg;
  jpeg.jpeg_quality = 95;
  if (Status st = WriteImage(path, image, jpeg); !st.ok()) return st;
  return JpegRowReader::Open(path, 3);
}

// RMS over pixels of the difference in linear chromaticity (r, g) = (R, G) / (R + G + B).
double ChromaticityRms(const Image& a, const Image& b) {
  double sum = 0;
  for (size_t i = 0; i < a.pixel_count(); ++i) {
    const float* p = a.data() + 3 * i;
    const float* q = b.data() + 3 * i;
    const double sp = std::max(1e-6f, p[0] + p[1] + p[2]), sq = std::max(1e-6f, q[0] + q[1] + q[2]);
    for (int c = 0; c < 2; ++c) sum += std::pow(p[c] / sp - q[c] / sq, 2);
  }
  return std::sqrt(sum / double(2 * a.pixel_count()));
}

double MaxDifference(const Image& a, const Image& b) {
  double worst = 0;
  for (size_t i = 0; i < a.size(); ++i) worst = std::max(worst, double(std::abs(a.data()[i] - b.data()[i])));
  return worst;
}

Image PlainLinear(const ImageU8& srgb) {
  Image out(srgb.width(), srgb.height(), srgb.channels());
  for (size_t i = 0; i < srgb.size(); ++i) out.data()[i] = SrgbToLinear(srgb.data()[i] / 255.0f);
  return out;
}

TEST(ChromaDetail, RestoresTheColourOfDetailFinerThanTheChroma) {
  const auto dir = testing::MakeTempDir();
  const Image original = TwoColourDetail(160, 120);
  auto jpeg = WriteJpeg(dir / "shot.jpg", original);
  ASSERT_TRUE(jpeg.ok() && *jpeg) << (jpeg.ok() ? "not a JPEG" : jpeg.status().message());
  ASSERT_TRUE((*jpeg)->chroma_subsampled());
  ASSERT_TRUE(ChromaDetailRestorable((*jpeg)->chroma_factors()));
  auto srgb = (*jpeg)->ReadAll();
  ASSERT_TRUE(srgb.ok()) << srgb.status().message();
  const Image plain = PlainLinear(*srgb), restored = LinearWithChromaDetail(*srgb, (*jpeg)->chroma_factors());
  const double plain_error = ChromaticityRms(plain, original), restored_error = ChromaticityRms(restored, original);
  EXPECT_GT(plain_error, 0.01) << "the JPEG should have lost colour contrast";
  EXPECT_LT(restored_error, 0.5 * plain_error) << plain_error << " -> " << restored_error;
}

TEST(ChromaDetail, GreyAndFlatColourComeBackAsDecoded) {
  const auto dir = testing::MakeTempDir();
  Image grey(96, 64, 3), flat(96, 64, 3);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 96; ++x)
      for (int c = 0; c < 3; ++c) {
        grey.at(x, y, c) = 0.5f + 0.4f * std::sin(1.3f * x) * std::cos(0.9f * y);
        flat.at(x, y, c) = c == 0 ? 0.6f : c == 1 ? 0.3f : 0.2f;
      }
  for (const auto& [name, image] : {std::pair{"grey.jpg", &grey}, std::pair{"flat.jpg", &flat}}) {
    auto jpeg = WriteJpeg(dir / name, *image);
    ASSERT_TRUE(jpeg.ok() && *jpeg);
    auto srgb = (*jpeg)->ReadAll();
    ASSERT_TRUE(srgb.ok());
    // Nothing in the luma's detail goes with the colour: the decode is kept (to the linear
    // table's 1e-6).
    EXPECT_LT(MaxDifference(LinearWithChromaDetail(*srgb, (*jpeg)->chroma_factors()), PlainLinear(*srgb)), 1e-5) << name;
  }
}

TEST(ChromaDetail, BandsDoNotChangeTheResult) {
  const auto dir = testing::MakeTempDir();
  auto jpeg = WriteJpeg(dir / "shot.jpg", TwoColourDetail(70, 133));  // odd sizes: a last lone pair
  ASSERT_TRUE(jpeg.ok() && *jpeg);
  auto srgb = (*jpeg)->ReadAll();
  ASSERT_TRUE(srgb.ok());
  const auto factors = (*jpeg)->chroma_factors();
  const Image whole = LinearWithChromaDetail(*srgb, factors, 134);
  for (int band_rows : {2, 16, 64}) EXPECT_EQ(MaxDifference(LinearWithChromaDetail(*srgb, factors, band_rows), whole), 0.0) << band_rows;
}

TEST(ChromaDetail, RegionsGetTheWholeImagesRestorationAndTheRestStaysPlain) {
  const auto dir = testing::MakeTempDir();
  auto jpeg = WriteJpeg(dir / "shot.jpg", TwoColourDetail(151, 133));
  ASSERT_TRUE(jpeg.ok() && *jpeg);
  auto srgb = (*jpeg)->ReadAll();
  ASSERT_TRUE(srgb.ok());
  const auto factors = (*jpeg)->chroma_factors();
  const Image whole = LinearWithChromaDetail(*srgb, factors), plain = PlainLinear(*srgb);
  // Odd corners, overlapping, one past the image's edges, one empty.
  const std::vector<PixelRect> regions = {{13, 21, 40, 58}, {31, 45, 77, 50}, {120, 101, 200, 170}, {5, 5, 5, 9}};
  const Image part = LinearWithChromaDetail(*srgb, factors, 16, regions);
  int restored = 0, kept = 0;
  for (int y = 0; y < whole.height(); ++y)
    for (int x = 0; x < whole.width(); ++x) {
      const bool inside = std::any_of(regions.begin(), regions.end(), [&](const PixelRect& r) {
        return x >= r.x0 && x < r.x1 && y >= r.y0 && y < r.y1;
      });
      for (int c = 0; c < 3; ++c) {
        if (inside) {
          ASSERT_EQ(part.at(x, y, c), whole.at(x, y, c)) << x << "," << y;
          continue;
        }
        // Outside: the plain decode (the linear table's 1e-6), or a band's spill of the restoration.
        const bool as_plain = std::abs(part.at(x, y, c) - plain.at(x, y, c)) < 1e-5f;
        ASSERT_TRUE(as_plain || part.at(x, y, c) == whole.at(x, y, c)) << x << "," << y;
        if (c == 0) kept += as_plain && whole.at(x, y, c) != part.at(x, y, c);
      }
      restored += inside;
    }
  EXPECT_GT(restored, 2000);
  EXPECT_GT(kept, 5000) << "most of the image outside the regions should keep the plain decode";
}

TEST(ChromaDetail, FullResolutionColourIsOnlyLinearised) {
  EXPECT_FALSE(ChromaDetailRestorable({1, 1}));
  EXPECT_FALSE(ChromaDetailRestorable({4, 1}));  // 4:1:1: not undone
  EXPECT_TRUE(ChromaDetailRestorable({2, 1}));
  ImageU8 srgb(5, 4, 3);
  for (size_t i = 0; i < srgb.size(); ++i) srgb.data()[i] = uint8_t(i * 37 % 256);
  EXPECT_EQ(MaxDifference(LinearWithChromaDetail(srgb, {1, 1}), PlainLinear(srgb)), 0.0);
}

}  // namespace
}  // namespace mesocap
