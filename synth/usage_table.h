// How many output texels each sample texel fills, summed over sample boxes in O(1) (a summed-area
// table): the usage balance of block synthesis and quilting, which prefer the least used part of
// the sample so that its border band and its busy regions are drawn on as often as the rest.
#pragma once

#include <algorithm>
#include <optional>
#include <vector>

#include <Eigen/Core>

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

// The counts themselves, changed texel by texel as a synthesis places and replaces texels, and
// their table, rebuilt on the first query after a change.
class SampleUsage {
 public:
  SampleUsage(int width, int height) : width_(width), height_(height), counts_(size_t(width) * height, 0.0) {}
  void Add(const Eigen::Vector2i& texel, double count) {
    counts_[size_t(texel.y()) * width_ + texel.x()] += count;
    total_ += count;
    table_.reset();
  }
  double total() const { return total_; }
  const UsageTable& Table() {
    if (!table_) table_.emplace(counts_, width_, height_);
    return *table_;
  }
  // The usage of the box of `radius` around `texel` (clamped into the sample) over its share under
  // uniform use: 1 where the sample is used as much as on average. Needs a total above 0.
  double Crowding(const Eigen::Vector2i& texel, int radius) {
    const int x0 = std::max(0, texel.x() - radius), y0 = std::max(0, texel.y() - radius);
    const int x1 = std::min(width_, texel.x() + radius + 1), y1 = std::min(height_, texel.y() + radius + 1);
    const double share = total_ / (double(width_) * height_) * double(x1 - x0) * (y1 - y0);
    return Table().Sum(x0, y0, x1, y1) / share;
  }

 private:
  int width_, height_;
  std::vector<double> counts_;
  double total_ = 0;
  std::optional<UsageTable> table_;
};

}  // namespace mesocap
