#include "reconstruct/quantiles.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <stdexcept>
#include <vector>

#include "tests/testing.h"

namespace mesocap {
namespace {

InverseCdf Linear(float lo, float hi, int count = kDefaultQuantiles) {
  InverseCdf q;
  for (int k = 0; k < count; ++k) q.values.push_back(lo + (hi - lo) * float(k) / float(count - 1));
  return q;
}

TEST(InverseCdf, AtAndMeanOfLinear) {
  const InverseCdf q = Linear(2, 6, 5);
  EXPECT_FLOAT_EQ(q.At(0), 2);
  EXPECT_FLOAT_EQ(q.At(1), 6);
  EXPECT_FLOAT_EQ(q.At(0.3), 3.2f);
  EXPECT_FLOAT_EQ(q.At(-1), 2);  // clamped
  EXPECT_FLOAT_EQ(q.At(2), 6);
  EXPECT_DOUBLE_EQ(q.Mean(), 4);
  EXPECT_THROW(InverseCdf{}.At(0.5), std::invalid_argument);
}

TEST(InverseCdfOf, EvenlySpacedSamplesGiveLinearQuantiles) {
  std::mt19937 rng(testing::SeedFromTestName());
  for (const int n : {101, 4001}) {  // std::sort and radix-sort paths
    std::vector<float> samples(n);
    for (int i = 0; i < n; ++i) samples[i] = -1.0f + 3.0f * float(i) / float(n - 1);
    std::shuffle(samples.begin(), samples.end(), rng);
    const std::vector<float> copy = samples;
    const InverseCdf q = InverseCdfOf(samples, 11);
    ASSERT_EQ(q.values.size(), 11u);
    EXPECT_EQ(samples, copy);  // not modified
    for (int k = 0; k <= 10; ++k) EXPECT_NEAR(q.values[k], -1.0 + 3.0 * k / 10.0, 1e-6) << n << " " << k;
    EXPECT_EQ(q.values.front(), -1.0f);
    EXPECT_EQ(q.values.back(), 2.0f);
  }
}

TEST(InverseCdfOf, UniformNoiseIsNearlyLinear) {
  std::mt19937 rng(testing::SeedFromTestName());
  std::uniform_real_distribution<float> uniform(-2, 5);
  std::vector<float> samples(65536);
  for (float& s : samples) s = uniform(rng);
  const InverseCdf q = InverseCdfOf(samples);
  ASSERT_EQ(int(q.values.size()), kDefaultQuantiles);
  EXPECT_TRUE(std::is_sorted(q.values.begin(), q.values.end()));
  for (int k = 0; k < kDefaultQuantiles; ++k) EXPECT_NEAR(q.values[k], -2 + 7.0 * k / (kDefaultQuantiles - 1), 0.05);
  EXPECT_EQ(q.values.front(), *std::min_element(samples.begin(), samples.end()));
  EXPECT_EQ(q.values.back(), *std::max_element(samples.begin(), samples.end()));
}

TEST(InverseCdfOf, NegativeValuesAndSignedZeros) {
  std::vector<float> samples(3000);
  for (size_t i = 0; i < samples.size(); ++i) samples[i] = (i % 3 == 0) ? -0.0f : (i % 3 == 1 ? -float(i) : float(i));
  const InverseCdf q = InverseCdfOf(samples, 3);
  EXPECT_EQ(q.values[0], -2998.0f);
  EXPECT_EQ(q.values[1], 0.0f);
  EXPECT_EQ(q.values[2], 2999.0f);
}

TEST(InverseCdfOf, RejectsBadInput) {
  EXPECT_THROW(InverseCdfOf(std::vector<float>{}), std::invalid_argument);
  EXPECT_THROW(InverseCdfOf(std::vector<float>{1, 2}, 1), std::invalid_argument);
}

TEST(BlendInverseCdfs, HalfHalfOfTwoUniformsIsTheUniformBetween) {
  const InverseCdf a = Linear(0, 1), b = Linear(2, 3);
  const InverseCdf* cdfs[] = {&a, &b};
  const double weights[] = {0.5, 0.5};
  const InverseCdf blend = BlendInverseCdfs(cdfs, weights);
  const InverseCdf expected = Linear(1, 2);
  ASSERT_EQ(blend.values.size(), expected.values.size());
  for (size_t k = 0; k < blend.values.size(); ++k) EXPECT_NEAR(blend.values[k], expected.values[k], 1e-6);
  EXPECT_NEAR(blend.Mean(), 1.5, 1e-6);
}

TEST(BlendInverseCdfs, NegativeWeightsExtrapolateLinearly) {
  // 1.5 U[0,1] - 0.5 U[0,2] = U[0,0.5]: monotone without any fix.
  const InverseCdf a = Linear(0, 1), b = Linear(0, 2);
  const InverseCdf* cdfs[] = {&a, &b};
  const double weights[] = {1.5, -0.5};
  const InverseCdf blend = BlendInverseCdfs(cdfs, weights);
  const InverseCdf expected = Linear(0, 0.5);
  for (size_t k = 0; k < blend.values.size(); ++k) EXPECT_NEAR(blend.values[k], expected.values[k], 1e-6);
}

TEST(BlendInverseCdfs, NegativeWeightsStayMonotone) {
  // 2 p - 2 p^2 rises up to p = 1/2 and falls after: the result keeps its running maximum.
  InverseCdf a = Linear(0, 1), b;
  for (float v : a.values) b.values.push_back(2 * v * v);
  const InverseCdf* cdfs[] = {&a, &b};
  const double weights[] = {2.0, -1.0};
  const InverseCdf blend = BlendInverseCdfs(cdfs, weights);
  EXPECT_TRUE(std::is_sorted(blend.values.begin(), blend.values.end()));
  for (size_t k = 0; k < blend.values.size(); ++k) {
    const double p = double(k) / (blend.values.size() - 1);
    const double raw = 2 * p - 2 * p * p;
    EXPECT_NEAR(blend.values[k], p <= 0.5 ? raw : 0.5, 1e-5) << p;
  }
}

TEST(BlendInverseCdfs, ANegatedInputIsTheDistributionOfMinusX) {
  // U[1,3] negated is U[-3,-1]: half of it with half of U[5,7] is U[1,3] again.
  const InverseCdf a = Linear(1, 3), b = Linear(5, 7);
  const InverseCdf* cdfs[] = {&a, &b};
  const double weights[] = {0.5, 0.5};
  const char negated[] = {1, 0};
  const InverseCdf blend = BlendInverseCdfs(cdfs, weights, negated);
  for (size_t k = 0; k < blend.values.size(); ++k) EXPECT_NEAR(blend.values[k], a.values[k], 1e-6);
  const char wrong_count[] = {1};
  EXPECT_THROW(BlendInverseCdfs(cdfs, weights, wrong_count), std::invalid_argument);
}

TEST(BlendInverseCdfs, RejectsMismatchedInput) {
  const InverseCdf a = Linear(0, 1), b = Linear(0, 1, 17);
  const InverseCdf* cdfs[] = {&a, &b};
  const double two[] = {0.5, 0.5}, one[] = {1.0};
  EXPECT_THROW(BlendInverseCdfs(cdfs, two), std::invalid_argument);
  EXPECT_THROW(BlendInverseCdfs(cdfs, one), std::invalid_argument);
}

TEST(MatchToInverseCdf, NoiseTakesTheTargetDistributionAndKeepsRanks) {
  std::mt19937 rng(testing::SeedFromTestName());
  std::normal_distribution<float> normal(0, 1);
  InverseCdf target;  // Q(p) = exp(2p) - 1, a skewed distribution on [0, e^2 - 1]
  for (int k = 0; k < kDefaultQuantiles; ++k) target.values.push_back(std::expm1(2.0f * k / (kDefaultQuantiles - 1)));
  for (const int n : {500, 65536}) {
    std::vector<float> values(n);
    for (float& v : values) v = normal(rng);
    const std::vector<float> before = values;
    MatchToInverseCdf(values, target);

    // Rank r of n took Q((r + 0.5) / n): the matched quantile at p is Q((p (n - 1) + 0.5) / n),
    // which is Q(p) up to the half-rank offset (visible only in a steep tail for small n).
    const InverseCdf matched = InverseCdfOf(values);
    const double range = target.values.back() - target.values.front();
    const int m = int(target.values.size());
    for (int k = 0; k < m; ++k) {
      const double p = double(k) / (m - 1);
      EXPECT_NEAR(matched.values[k], target.At((p * (n - 1) + 0.5) / n), 1e-3 * range) << n << " " << k;
      EXPECT_NEAR(matched.values[k], target.values[k], 0.01 * range) << n << " " << k;
    }
    EXPECT_LT(WassersteinDistance(matched, target), 2e-3 * range);
    std::vector<uint32_t> by_before(n), by_after(n);
    std::iota(by_before.begin(), by_before.end(), 0u);
    by_after = by_before;
    std::stable_sort(by_before.begin(), by_before.end(), [&](uint32_t i, uint32_t j) { return before[i] < before[j]; });
    for (size_t r = 1; r < by_before.size(); ++r) ASSERT_LE(values[by_before[r - 1]], values[by_before[r]]);
  }
}

TEST(MatchToInverseCdf, TiesKeepTheirOrder) {
  for (const int n : {100, 5000}) {
    std::vector<float> values(n, 3.0f);
    MatchToInverseCdf(values, Linear(0, 1));
    for (int i = 0; i < n; ++i) EXPECT_NEAR(values[i], (i + 0.5) / n, 1e-6);
  }
}

TEST(WassersteinDistance, ShiftedCopiesAreTheShiftApart) {
  std::mt19937 rng(testing::SeedFromTestName());
  std::gamma_distribution<float> gamma(2.0f, 1.5f);
  std::vector<float> samples(20000), shifted(20000);
  for (size_t i = 0; i < samples.size(); ++i) samples[i] = gamma(rng), shifted[i] = samples[i] + 0.75f;
  const InverseCdf a = InverseCdfOf(samples), b = InverseCdfOf(shifted);
  EXPECT_NEAR(WassersteinDistance(a, b), 0.75, 1e-5);
  EXPECT_NEAR(WassersteinDistance(b, a), 0.75, 1e-5);
  EXPECT_NEAR(WassersteinDistance(a, a), 0.0, 1e-12);
  // Different sample counts: still exact for piecewise-linear quantile functions.
  EXPECT_NEAR(WassersteinDistance(Linear(0, 1, 5), Linear(0.25f, 1.25f, 9)), 0.25, 1e-6);
}

TEST(WassersteinDistance, CrossingQuantileFunctions) {
  // |p - 1/2| integrates to 1/4; the zero crossing falls inside the only interval.
  EXPECT_NEAR(WassersteinDistance(Linear(0, 1, 2), Linear(0.5f, 0.5f, 2)), 0.25, 1e-7);
  // U[0,1] against U[0.25,0.75]: |p - (0.25 + p/2)| = |p/2 - 1/4| integrates to 1/8.
  EXPECT_NEAR(WassersteinDistance(Linear(0, 1, 3), Linear(0.25f, 0.75f, 5)), 0.125, 1e-7);
}

}  // namespace
}  // namespace mesocap
