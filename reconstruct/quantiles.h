// Distributions stored as inverse CDFs (quantile functions) so they can be blended and
// extrapolated linearly, as Ngan & Durand do after Matusik et al. 2005: a blend of quantile
// functions with weights summing to one is again a distribution's quantile function (kept
// monotone when negative extrapolation weights would bend it), which a blend of histograms with
// negative weights is not.
#pragma once

#include <span>
#include <vector>

namespace mesocap {

// Q(p) sampled at p_k = k / (n - 1), k = 0..n-1: values[0] is the minimum, values.back() the
// maximum, linear in between. Non-decreasing.
struct InverseCdf {
  std::vector<float> values;

  bool empty() const { return values.empty(); }
  // Q(p) for p in [0, 1], linear between the stored samples.
  float At(double p) const;
  double Mean() const;  // integral of Q over [0, 1] (trapezoid rule)
};

inline constexpr int kDefaultQuantiles = 257;

// The empirical quantile function of `samples` (any order, not modified), at `count` points.
InverseCdf InverseCdfOf(std::span<const float> samples, int count = kDefaultQuantiles);

// sum_k weights[k] * Q_k, pointwise; all inputs the same length; weights should sum to one and
// may be negative. The result is made non-decreasing (running maximum) so extrapolation cannot
// yield an invalid distribution.
InverseCdf BlendInverseCdfs(std::span<const InverseCdf* const> cdfs, std::span<const double> weights);
// The same with some inputs negated: where negated[k] is set, Q_k stands for the distribution of
// -X, Q(p) -> -Q_k(1 - p) (no copy is made of it).
InverseCdf BlendInverseCdfs(std::span<const InverseCdf* const> cdfs, std::span<const double> weights,
                            std::span<const char> negated);

// Histogram matching: remaps `values` in place, keeping their ranks, so their distribution is
// `target` (the value of rank r of n takes Q((r + 0.5) / n)). Ties keep a stable order.
void MatchToInverseCdf(std::span<float> values, const InverseCdf& target);

// 1-D Wasserstein-1 distance between two distributions: integral over p of |Q_a(p) - Q_b(p)|.
double WassersteinDistance(const InverseCdf& a, const InverseCdf& b);

}  // namespace mesocap
