// The upper median of a list (the element at size / 2 in sorted order; 0 for an empty list): the
// figure the project's tables and reports show. Any arithmetic element type: float lists (texel
// errors, pixel values) need no copy to double.
#pragma once

#include <algorithm>
#include <vector>

namespace mesocap {

template <typename T>
T UpperMedian(std::vector<T> values) {
  if (values.empty()) return T(0);
  std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
  return values[values.size() / 2];
}

}  // namespace mesocap
