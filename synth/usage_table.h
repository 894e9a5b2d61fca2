// How many output texels each sample texel fills, summed over sample boxes in O(1) (a summed-area
// table): the usage balance of block synthesis and quilting, which try the least used part of the
// sample first so that its border band is drawn on as often as its centre.
#pragma once

#include <algorithm>
#include <vector>

namespace mesocap {

class UsageTable {
 public:
  // `usage`: row-major, width x height.
  UsageTable(const std::vector<double>& usage, int width, int height)
      : width_(width), height_(height), table_(size_t(width + 1) * (height + 1)) {
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x)
        table_[size_t(y + 1) * (width + 1) + x + 1] = usage[size_t(y) * width + x] + at(x + 1, y) + at(x, y + 1) - at(x, y);
  }
  // Texels x0 <= x < x1, y0 <= y < y1, clamped into the sample.
  double Sum(int x0, int y0, int x1, int y1) const {
    x0 = std::clamp(x0, 0, width_), x1 = std::clamp(x1, 0, width_);
    y0 = std::clamp(y0, 0, height_), y1 = std::clamp(y1, 0, height_);
    if (x1 <= x0 || y1 <= y0) return 0;
    return at(x1, y1) - at(x0, y1) - at(x1, y0) + at(x0, y0);
  }
  double Block(int x, int y, int side) const { return Sum(x, y, x + side, y + side); }

 private:
  double at(int x, int y) const { return table_[size_t(y) * (width_ + 1) + x]; }
  int width_, height_;
  std::vector<double> table_;
};

}  // namespace mesocap
