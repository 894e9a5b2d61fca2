// The Euclidean distance between two texels' feature vectors (n floats each, summed in double):
// the graphcut's seam costs, the roller's tile edges, block synthesis' step errors and the seam
// quality measure all compare texels by it.
#pragma once

#include <cmath>

namespace mesocap {

inline double FeatureDistanceSquared(const float* a, const float* b, int n) {
  double sum = 0;
  for (int i = 0; i < n; ++i) sum += double(a[i] - b[i]) * (a[i] - b[i]);
  return sum;
}

inline double FeatureDistance(const float* a, const float* b, int n) { return std::sqrt(FeatureDistanceSquared(a, b, n)); }

}  // namespace mesocap
