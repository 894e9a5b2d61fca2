#include "reconstruct/colour.h"

#include <cmath>
#include <limits>
#include <random>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "tests/testing.h"

namespace mesocap {
namespace {

// Colours spread mostly along `axis` (a unit vector), a little along a second direction.
Image ColoursAlong(const Eigen::Vector3f& axis, int size, uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> wide(0, 0.5f), narrow(0, 0.05f);  // colours stay positive
  const Eigen::Vector3f other = axis.unitOrthogonal();
  Image image(size, size, 3);
  for (size_t i = 0; i < image.pixel_count(); ++i)
    Eigen::Map<Eigen::Vector3f>(image.data() + 3 * i) = Eigen::Vector3f(3, 3, 3) + wide(rng) * axis + narrow(rng) * other;
  return image;
}

TEST(Colour, TheFirstAxisIsTheDirectionOfLargestVarianceAndTheBasisIsOrthonormal) {
  const Eigen::Vector3f axis = Eigen::Vector3f(0.8f, 0.5f, 0.2f).normalized();
  const Image image = ColoursAlong(axis, 128, testing::SeedFromTestName());
  const Eigen::Matrix3f basis = DecorrelatingColourBasis(std::span(&image, 1));
  EXPECT_LT((basis * basis.transpose() - Eigen::Matrix3f::Identity()).cwiseAbs().maxCoeff(), 1e-5f);
  EXPECT_GT(basis.row(0).dot(axis), 0.999f);  // signed so its largest component is positive
  // The decorrelated channels are uncorrelated.
  const ColourChannels channels = ColourChannels::For(ColourSpace::kPrincipalAxes, std::span(&image, 1));
  EXPECT_EQ(channels.basis(), basis);
  const Image turned = channels.Forward(image);
  Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < turned.pixel_count(); ++i) {
    const Eigen::Vector3d c = Eigen::Map<const Eigen::Vector3f>(turned.data() + 3 * i).cast<double>();
    mean += c, second += c * c.transpose();
  }
  const double n = double(turned.pixel_count());
  const Eigen::Matrix3d covariance = second / n - (mean / n) * (mean / n).transpose();
  EXPECT_LT(std::abs(covariance(0, 1)) + std::abs(covariance(0, 2)) + std::abs(covariance(1, 2)), 1e-3 * covariance(0, 0));
  // And back.
  const Image back = channels.Inverse(turned);
  for (size_t i = 0; i < image.size(); ++i) ASSERT_NEAR(back.data()[i], image.data()[i], 1e-5f);
}

TEST(Colour, OneChannelImagesAndFlatColoursKeepTheIdentity) {
  const Image grey(16, 16, 1);
  EXPECT_TRUE(DecorrelatingColourBasis(std::span(&grey, 1)).isIdentity());
  Image flat(16, 16, 3);
  for (size_t i = 0; i < flat.size(); ++i) flat.data()[i] = 0.5f;
  EXPECT_TRUE(DecorrelatingColourBasis(std::span(&flat, 1)).isIdentity());
  EXPECT_EQ(ColourChannels::For(ColourSpace::kChromaticity, {}).Forward(grey), grey);
}

TEST(Colour, ChromaticityChannelsAreBrightnessAndRatiosAndGoBack) {
  Image image(3, 1, 3);
  const float texels[3][3] = {{0.4f, 0.2f, 0.2f}, {0, 0, 0}, {1, 2, 1}};
  std::copy_n(&texels[0][0], 9, image.data());
  const ColourChannels chromaticity = ColourChannels::For(ColourSpace::kChromaticity, {});
  const Image c = chromaticity.Forward(image);
  EXPECT_FLOAT_EQ(c.at(0, 0, 0), 0.8f);
  EXPECT_FLOAT_EQ(c.at(0, 0, 1), 0.5f);
  EXPECT_FLOAT_EQ(c.at(0, 0, 2), 0.25f);
  EXPECT_FLOAT_EQ(c.at(1, 0, 1), 1.0f / 3);  // black: grey
  const Image back = chromaticity.Inverse(c);
  for (size_t i = 0; i < image.size(); ++i) EXPECT_NEAR(back.data()[i], image.data()[i], 1e-6f);
  // Chromaticities whose sum passes one (a matched histogram can) give no negative blue.
  Image off = c;
  off.at(2, 0, 1) = 0.7f, off.at(2, 0, 2) = 0.5f;
  EXPECT_EQ(chromaticity.Inverse(off).at(2, 0, 2), 0.0f);
  EXPECT_EQ(ParseColourSpace(ColourSpaceName(ColourSpace::kChromaticity)), ColourSpace::kChromaticity);
  EXPECT_FALSE(ParseColourSpace("hsv"));
}

TEST(Colour, StorableRadianceIsFiniteAndNonNegative) {
  Image image(4, 1, 1);
  image.data()[0] = -0.5f;
  image.data()[1] = std::numeric_limits<float>::quiet_NaN();
  image.data()[2] = std::numeric_limits<float>::infinity();
  image.data()[3] = 1e6f;
  ClampToStorableRadiance(&image);
  EXPECT_EQ(image.data()[0], 0.0f);
  EXPECT_EQ(image.data()[1], 0.0f);
  EXPECT_EQ(image.data()[2], 0.0f);
  EXPECT_EQ(image.data()[3], 65504.0f);
}

Image Uniform(int size, float r, float g, float b) {
  Image image(size, size, 3);
  for (size_t i = 0; i < image.pixel_count(); ++i) image.data()[3 * i] = r, image.data()[3 * i + 1] = g, image.data()[3 * i + 2] = b;
  return image;
}

TEST(Colour, ChromaticityDistanceAndSaturationHaveTheirClosedForms) {
  // Grey: r = g = 1/3. (2, 1, 1) at any brightness: r = 1/2, g = 1/4.
  const Image grey = Uniform(8, 0.3f, 0.3f, 0.3f), reddish = Uniform(8, 0.4f, 0.2f, 0.2f);
  EXPECT_NEAR(ChromaticityDistance(grey, reddish), 0.5 * ((0.5 - 1.0 / 3) + (1.0 / 3 - 0.25)), 1e-6);
  EXPECT_NEAR(ChromaticityDistance(reddish, Uniform(8, 4, 2, 2)), 0.0, 1e-7);  // brightness does not count
  EXPECT_NEAR(SaturationQuantile(grey, 0.95), 0.0, 1e-7);
  EXPECT_NEAR(SaturationQuantile(reddish, 0.95), 0.5, 1e-6);
  // Half the texels at saturation 0.5, half at 0.75: the 95th percentile is 0.75, the 25th 0.5.
  Image mixed = reddish;
  for (size_t i = 0; i < mixed.pixel_count() / 2; ++i) mixed.data()[3 * i + 1] = mixed.data()[3 * i + 2] = 0.1f;
  EXPECT_NEAR(SaturationQuantile(mixed, 0.95), 0.75, 1e-6);
  EXPECT_NEAR(SaturationQuantile(mixed, 0.25), 0.5, 1e-6);
}

}  // namespace
}  // namespace mesocap
