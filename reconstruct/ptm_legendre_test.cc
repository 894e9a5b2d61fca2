#include "reconstruct/ptm_legendre.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "tests/testing.h"

namespace mesocap {
namespace {

// 3-point Gauss-Legendre on [-1, 1]: exact for polynomials of degree <= 5 per axis, so for every
// product of two biquadratics (degree <= 4 per axis) below.
constexpr double kNodes[3] = {-0.7745966692414834, 0.0, 0.7745966692414834};
constexpr double kWeights[3] = {5.0 / 9, 8.0 / 9, 5.0 / 9};

template <typename F>
double IntegrateSquare(const F& f) {
  double sum = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) sum += kWeights[i] * kWeights[j] * f(kNodes[i], kNodes[j]);
  return sum;
}

double PtmValue(const Eigen::Matrix<double, 6, 1>& a, double u, double v) {
  return a[0] * u * u + a[1] * v * v + a[2] * u * v + a[3] * u + a[4] * v + a[5];
}

TEST(PtmLegendre, TheBasisIsOrthonormalOnTheSquare) {
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) {
      const double inner = IntegrateSquare([&](double u, double v) { return LegendreBasis(u, v)[i] * LegendreBasis(u, v)[j]; });
      EXPECT_NEAR(inner, i == j ? 1.0 : 0.0, 1e-12) << i << "," << j;
    }
}

// The same function in both bases, and coefficient distances equal to L2 distances between the
// functions over the square: what block synthesis compares.
TEST(PtmLegendre, SameFunctionAndDistancesAreFunctionDistances) {
  std::mt19937 rng(testing::SeedFromTestName());
  std::uniform_real_distribution<double> coefficient(-1, 1), point(-1, 1);
  for (int trial = 0; trial < 50; ++trial) {
    Eigen::Matrix<double, 6, 1> a1, a2;
    for (int k = 0; k < 6; ++k) a1[k] = coefficient(rng), a2[k] = coefficient(rng);
    const Eigen::Matrix<double, 6, 1> b1 = PtmToLegendreMatrix() * a1, b2 = PtmToLegendreMatrix() * a2;
    for (int p = 0; p < 5; ++p) {
      const double u = point(rng), v = point(rng);
      EXPECT_NEAR(LegendreBasis(u, v).dot(b1), PtmValue(a1, u, v), 1e-12);
    }
    const double l2 = IntegrateSquare([&](double u, double v) { return std::pow(PtmValue(a1, u, v) - PtmValue(a2, u, v), 2); });
    EXPECT_NEAR((b1 - b2).squaredNorm(), l2, 1e-10 * (1 + l2));
    EXPECT_LT((LegendreToPtmMatrix() * b1 - a1).norm(), 1e-12);
  }
}

Ptm RandomPtm(PtmFormat format, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> coefficient(-0.5f, 0.9f), colour(0.05f, 1.0f);
  Ptm ptm;
  ptm.format = format;
  ptm.coefficients = Image(17, 9, format == PtmFormat::kLrgb ? 6 : 18);
  for (size_t i = 0; i < ptm.coefficients.size(); ++i) ptm.coefficients.data()[i] = coefficient(rng);
  if (format == PtmFormat::kLrgb) {
    ptm.rgb = Image(17, 9, 3);
    for (size_t i = 0; i < ptm.rgb.size(); ++i) ptm.rgb.data()[i] = colour(rng);
  }
  return ptm;
}

// PTM -> Legendre -> PTM within 1e-6 relative, and relighting from either agrees.
TEST(PtmLegendre, RoundTripOfLrgbAndRgbPtms) {
  for (PtmFormat format : {PtmFormat::kRgb, PtmFormat::kLrgb}) {
    const Ptm ptm = RandomPtm(format, testing::SeedFromTestName() + int(format));
    const Ptm back = PtmFromLegendreCoefficients(PtmLegendreCoefficients(ptm));
    ASSERT_EQ(back.format, PtmFormat::kRgb);
    for (int y = 0; y < ptm.height(); ++y)
      for (int x = 0; x < ptm.width(); ++x)
        for (int c = 0; c < 3; ++c)
          for (int k = 0; k < 6; ++k) {
            const double original = format == PtmFormat::kLrgb ? double(ptm.coefficients.at(x, y, k)) * ptm.rgb.at(x, y, c)
                                                               : ptm.coefficients.at(x, y, 6 * c + k);
            EXPECT_NEAR(back.coefficients.at(x, y, 6 * c + k), original, 1e-6 * (1 + std::abs(original)));
          }
    for (const Eigen::Vector3d& light : {Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(0.5, -0.3, 0.8), Eigen::Vector3d(-0.7, 0.2, 0.4)}) {
      const Image a = RelightPtm(ptm, light, /*clamp=*/false), b = RelightPtm(back, light, /*clamp=*/false);
      ASSERT_EQ(a.size(), b.size());
      for (size_t i = 0; i < a.size(); ++i) EXPECT_NEAR(a.data()[i], b.data()[i], 1e-5);
    }
  }
}

}  // namespace
}  // namespace mesocap
