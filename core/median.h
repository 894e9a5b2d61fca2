// The upper median of a list (the element at size / 2 in sorted order; 0 for an empty list): the
// figure the project's tables and reports show.
#pragma once

#include <algorithm>
#include <vector>

namespace mesocap {

inline double UpperMedian(std::vector<double> values) {
  if (values.empty()) return 0;
  std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
  return values[values.size() / 2];
}

}  // namespace mesocap
