// The per-pixel maximum and sum of flash shots, where the balls are found (calib/spheres.h):
// `calibrate` adds every shot as it decodes them, the capture guide each shot as it arrives.
#pragma once

#include <algorithm>
#include <array>
#include <atomic>
#include <limits>
#include <mutex>
#include <vector>

#include "core/image.h"

namespace mesocap {

// The per-pixel maximum and sum of the flash shots, added as each shot is decoded. The sum is kept
// in doubles, where shots of 8-bit, 16-bit or half-float values (each a multiple of 2^-40, a
// thousand of them summing below 2^13) add exactly, so it does not depend on the order the shots
// finish in (a float sum did, in its last bits, and so did every ball fitted to it). Bands of
// rows have their own locks: two threads add two shots at once.
class ShotAccumulator {
 public:
  static constexpr int kBands = 32;

  void Add(const Image& shot) {
    {
      std::lock_guard<std::mutex> lock(shape_mutex_);
      if (max_.empty()) {
        max_ = Image(shot.width(), shot.height(), shot.channels(), -std::numeric_limits<float>::infinity());
        sum_.assign(shot.size(), 0.0);
      }
      if (max_.width() != shot.width() || max_.height() != shot.height() || max_.channels() != shot.channels()) return;
    }
    const size_t values = shot.size(), band_values = (values + kBands - 1) / kBands;
    const int first = int(next_band_++ % kBands);  // threads start at different bands
    for (int k = 0; k < kBands; ++k) {
      const int band = (first + k) % kBands;
      const size_t begin = size_t(band) * band_values, end = std::min(values, begin + band_values);
      std::lock_guard<std::mutex> lock(band_mutex_[band]);
      const float* v = shot.data();
      float* max = max_.data();
      for (size_t i = begin; i < end; ++i) {
        max[i] = std::max(max[i], v[i]);
        sum_[i] += double(v[i]);
      }
    }
  }
  bool empty() const { return max_.empty(); }
  const Image& max() const { return max_; }
  Image TakeMax() { return std::move(max_); }
  void Clear() {
    max_ = Image();
    sum_ = std::vector<double>();
  }
  Image Sum() const {
    Image sum(max_.width(), max_.height(), max_.channels());
    for (size_t i = 0; i < sum_.size(); ++i) sum.data()[i] = float(sum_[i]);
    return sum;
  }

 private:
  std::mutex shape_mutex_;
  std::array<std::mutex, kBands> band_mutex_;
  std::atomic<unsigned> next_band_{0};
  Image max_;
  std::vector<double> sum_;
};

}  // namespace mesocap
