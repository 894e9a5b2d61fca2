#include "reconstruct/steerable_pyramid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <thread>
#include <vector>

#include "tests/testing.h"

namespace mesocap {
namespace {

constexpr double kPi = 3.14159265358979323846;

std::vector<float> Noise(int width, int height, std::mt19937& rng) {
  std::normal_distribution<float> normal(0.3f, 1.0f);
  std::vector<float> plane(size_t(width) * height);
  for (float& v : plane) v = normal(rng);
  return plane;
}

// A smooth, non-periodic plane: a few random low-frequency waves plus a ramp.
std::vector<float> Smooth(int width, int height, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<float> plane(size_t(width) * height);
  double wave[4][4];
  for (auto& w : wave) w[0] = 3 * u(rng), w[1] = 3 * u(rng), w[2] = 2 * kPi * u(rng), w[3] = u(rng);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const double sx = double(x) / width, sy = double(y) / height;
      double v = 0.5 + 0.8 * sx - 0.3 * sy;
      for (auto& w : wave) v += w[3] * std::sin(2 * kPi * (w[0] * sx + w[1] * sy) + w[2]);
      plane[size_t(y) * width + x] = float(v);
    }
  return plane;
}

double MaxAbs(const std::vector<float>& v) {
  double m = 0;
  for (float x : v) m = std::max(m, double(std::abs(x)));
  return m;
}

double Energy(const std::vector<float>& v) {
  double e = 0;
  for (float x : v) e += double(x) * x;
  return e;
}

double RelativeRoundTripError(const std::vector<float>& plane, const SteerablePyramid& pyramid) {
  const std::vector<float> back = CollapseSteerablePyramid(pyramid);
  EXPECT_EQ(back.size(), plane.size());
  double err = 0;
  for (size_t i = 0; i < plane.size(); ++i) err = std::max(err, double(std::abs(back[i] - plane[i])));
  return err / MaxAbs(plane);
}

double BandEnergy(const SteerablePyramid& pyramid) {
  double e = 0;
  for (const PyramidBand& band : pyramid.bands) e += Energy(band.values);
  return e;
}

struct Size {
  int width, height;
};

TEST(SteerablePyramid, RoundTripAndEnergyOnNoiseAndSmoothPlanes) {
  std::mt19937 rng(mesocap::testing::SeedFromTestName());
  for (const Size size : {Size{64, 64}, Size{256, 128}, Size{512, 512}}) {
    for (const bool smooth : {false, true}) {
      const std::vector<float> plane =
          smooth ? Smooth(size.width, size.height, rng) : Noise(size.width, size.height, rng);
      const SteerablePyramid pyramid = BuildSteerablePyramid(plane.data(), size.width, size.height);
      SCOPED_TRACE(std::to_string(size.width) + "x" + std::to_string(size.height) + (smooth ? " smooth" : " noise"));
      EXPECT_EQ(pyramid.levels, MaxPyramidLevels(size.width, size.height));
      EXPECT_LT(RelativeRoundTripError(plane, pyramid), 1e-4);
      // A tight frame with unitary transforms: unit weights for every band.
      EXPECT_NEAR(BandEnergy(pyramid) / Energy(plane), 1.0, 1e-4);
    }
  }
}

TEST(SteerablePyramid, RoundTripForEveryLevelCountAndOrientationCount) {
  std::mt19937 rng(mesocap::testing::SeedFromTestName());
  const std::vector<float> plane = Noise(64, 32, rng);
  for (int orientations : {1, 2, 3, 4, 6}) {
    for (int levels = 0; levels <= MaxPyramidLevels(64, 32); ++levels) {
      SteerablePyramidOptions options;
      options.orientations = orientations;
      options.levels = levels;
      const SteerablePyramid pyramid = BuildSteerablePyramid(plane.data(), 64, 32, options);
      SCOPED_TRACE(std::to_string(orientations) + " orientations, " + std::to_string(levels) + " levels");
      EXPECT_EQ(pyramid.band_count(), 2 + levels * orientations);
      EXPECT_LT(RelativeRoundTripError(plane, pyramid), 1e-4);
      EXPECT_NEAR(BandEnergy(pyramid) / Energy(plane), 1.0, 1e-4);
    }
  }
}

TEST(SteerablePyramid, OddAndSmallSizes) {
  std::mt19937 rng(mesocap::testing::SeedFromTestName());
  // Odd planes allow only the residuals; 24x40 with 3 levels ends on a 3x5 residual.
  for (const auto& [size, levels] : {std::pair{Size{45, 37}, 0}, std::pair{Size{24, 40}, 3}, std::pair{Size{8, 8}, 3}}) {
    const std::vector<float> plane = Noise(size.width, size.height, rng);
    SteerablePyramidOptions options;
    options.levels = levels;
    const SteerablePyramid pyramid = BuildSteerablePyramid(plane.data(), size.width, size.height, options);
    SCOPED_TRACE(std::to_string(size.width) + "x" + std::to_string(size.height));
    EXPECT_LT(RelativeRoundTripError(plane, pyramid), 1e-4);
    EXPECT_NEAR(BandEnergy(pyramid) / Energy(plane), 1.0, 1e-4);
  }
}

TEST(SteerablePyramid, BandSizesAsDocumented) {
  EXPECT_EQ(MaxPyramidLevels(256, 256), 5);
  EXPECT_EQ(MaxPyramidLevels(512, 512), 6);
  EXPECT_EQ(MaxPyramidLevels(256, 128), 4);
  EXPECT_EQ(MaxPyramidLevels(64, 64), 3);
  EXPECT_EQ(MaxPyramidLevels(96, 96), 3);  // 12x12 residual
  EXPECT_EQ(MaxPyramidLevels(100, 100), 2);  // divisible by 4 only
  EXPECT_EQ(MaxPyramidLevels(7, 7), 0);
  const std::vector<float> plane(256 * 128, 1.0f);
  const SteerablePyramid pyramid = BuildSteerablePyramid(plane.data(), 256, 128);
  EXPECT_EQ(pyramid.width, 256);
  EXPECT_EQ(pyramid.height, 128);
  EXPECT_EQ(pyramid.levels, 4);
  EXPECT_EQ(pyramid.orientations, 4);
  ASSERT_EQ(pyramid.band_count(), 2 + 4 * 4);
  EXPECT_EQ(pyramid.bands[0].width, 256);
  EXPECT_EQ(pyramid.bands[0].height, 128);
  for (int l = 0; l < 4; ++l)
    for (int o = 0; o < 4; ++o) {
      const PyramidBand& band = pyramid.bands[1 + l * 4 + o];
      EXPECT_EQ(band.width, 256 >> l);
      EXPECT_EQ(band.height, 128 >> l);
      EXPECT_EQ(band.values.size(), size_t(band.width) * band.height);
    }
  EXPECT_EQ(pyramid.bands.back().width, 16);
  EXPECT_EQ(pyramid.bands.back().height, 8);
  // A constant plane is all low-pass residual, at the unitary scale (mean * sqrt(n0 / n)).
  for (int b = 0; b + 1 < pyramid.band_count(); ++b) EXPECT_LT(MaxAbs(pyramid.bands[b].values), 1e-5) << b;
  for (float v : pyramid.bands.back().values) EXPECT_NEAR(v, 16.0f, 1e-4);
}

// The energy fraction of every band for a sinusoid with (kx, ky) cycles across the plane.
std::vector<double> BandEnergyFractions(int width, int height, int kx, int ky, SteerablePyramid* pyramid) {
  std::vector<float> plane(size_t(width) * height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      plane[size_t(y) * width + x] = float(std::cos(2 * kPi * (double(kx) * x / width + double(ky) * y / height) + 0.3));
  *pyramid = BuildSteerablePyramid(plane.data(), width, height);
  std::vector<double> fractions;
  for (const PyramidBand& band : pyramid->bands) fractions.push_back(Energy(band.values) / Energy(plane));
  return fractions;
}

TEST(SteerablePyramid, OrientedSinusoidLandsInItsBand) {
  // Level l is centred on a period of 4 * 2^l texels; orientation o on the frequency direction at
  // o * 45 degrees from +x towards +y (rows, downwards).
  struct Case {
    int width, height, kx, ky, level, orientation;
  };
  for (const Case c : {Case{128, 128, 8, 0, 2, 0}, Case{128, 128, 6, 6, 2, 1}, Case{128, 128, 0, 8, 2, 2},
                       Case{128, 128, -6, 6, 2, 3}, Case{128, 128, 23, 23, 0, 1}, Case{256, 128, 0, 16, 1, 2},
                       Case{256, 128, 8, 0, 3, 0}, Case{256, 128, -6, 3, 3, 3}}) {
    SteerablePyramid pyramid;
    const std::vector<double> fractions = BandEnergyFractions(c.width, c.height, c.kx, c.ky, &pyramid);
    const int expected = 1 + c.level * pyramid.orientations + c.orientation;
    SCOPED_TRACE(std::to_string(c.width) + "x" + std::to_string(c.height) + " k=(" + std::to_string(c.kx) + "," +
                 std::to_string(c.ky) + ")");
    EXPECT_EQ(std::max_element(fractions.begin(), fractions.end()) - fractions.begin(), expected);
    EXPECT_GT(fractions[expected], 0.6);
    // Orientations 90 degrees away get nothing.
    const int opposite = 1 + c.level * pyramid.orientations + (c.orientation + 2) % 4;
    EXPECT_LT(fractions[opposite], 0.02);
  }
}

TEST(SteerablePyramid, InvalidInputThrows) {
  const std::vector<float> plane(100 * 100, 0.0f);
  SteerablePyramidOptions options;
  options.levels = 3;  // 100 is not divisible by 8
  EXPECT_THROW(BuildSteerablePyramid(plane.data(), 100, 100, options), std::invalid_argument);
  EXPECT_NO_THROW(BuildSteerablePyramid(plane.data(), 100, 100));  // 2 levels
  EXPECT_THROW(BuildSteerablePyramid(plane.data(), 0, 100), std::invalid_argument);
  EXPECT_THROW(BuildSteerablePyramid(plane.data(), 100, -4), std::invalid_argument);
  EXPECT_THROW(BuildSteerablePyramid(nullptr, 100, 100), std::invalid_argument);
  options.levels = -2;
  EXPECT_FALSE(options.Check());
  EXPECT_THROW(BuildSteerablePyramid(plane.data(), 100, 100, options), std::invalid_argument);
  options = {};
  options.orientations = 0;
  EXPECT_FALSE(options.Check());
  EXPECT_THROW(BuildSteerablePyramid(plane.data(), 100, 100, options), std::invalid_argument);
  EXPECT_THROW(MaxPyramidLevels(0, 8), std::invalid_argument);

  SteerablePyramid pyramid = BuildSteerablePyramid(plane.data(), 100, 100);
  pyramid.bands[3].values.pop_back();
  EXPECT_THROW(CollapseSteerablePyramid(pyramid), std::invalid_argument);
  pyramid.bands.pop_back();
  EXPECT_THROW(CollapseSteerablePyramid(pyramid), std::invalid_argument);
}

TEST(SteerablePyramid, ConcurrentCallsMatchSerialOnes) {
  std::mt19937 rng(mesocap::testing::SeedFromTestName());
  const std::vector<Size> sizes = {{64, 64}, {96, 48}, {128, 128}, {80, 80}};
  std::vector<std::vector<float>> planes, serial;
  for (const Size s : sizes) planes.push_back(Noise(s.width, s.height, rng));
  for (size_t i = 0; i < sizes.size(); ++i)
    serial.push_back(CollapseSteerablePyramid(BuildSteerablePyramid(planes[i].data(), sizes[i].width, sizes[i].height)));
  std::vector<std::vector<float>> parallel(sizes.size());
  std::vector<std::thread> threads;
  for (size_t i = 0; i < sizes.size(); ++i)
    threads.emplace_back([&, i] {
      for (int repeat = 0; repeat < 5; ++repeat)
        parallel[i] =
            CollapseSteerablePyramid(BuildSteerablePyramid(planes[i].data(), sizes[i].width, sizes[i].height));
    });
  for (std::thread& t : threads) t.join();
  for (size_t i = 0; i < sizes.size(); ++i) EXPECT_EQ(parallel[i], serial[i]) << i;
}

}  // namespace
}  // namespace mesocap
