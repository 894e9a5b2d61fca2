// The one image type at the core: float, N interleaved channels, row-major, contiguous.
// Converts to cv::Mat without a copy (the Mat views this image's memory).
#pragma once

#include <cstddef>
#include <vector>

#include <opencv2/core.hpp>

namespace mesocap {

class Image {
 public:
  Image() = default;
  Image(int width, int height, int channels, float fill = 0.0f);

  int width() const { return width_; }
  int height() const { return height_; }
  int channels() const { return channels_; }
  bool empty() const { return data_.empty(); }
  size_t pixel_count() const { return size_t(width_) * size_t(height_); }
  size_t size() const { return data_.size(); }

  float* data() { return data_.data(); }
  const float* data() const { return data_.data(); }
  float* row(int y) { return data_.data() + size_t(y) * width_ * channels_; }
  const float* row(int y) const { return data_.data() + size_t(y) * width_ * channels_; }
  float* pixel(int x, int y) { return row(y) + size_t(x) * channels_; }
  const float* pixel(int x, int y) const { return row(y) + size_t(x) * channels_; }
  float& at(int x, int y, int c = 0) { return pixel(x, y)[c]; }
  float at(int x, int y, int c = 0) const { return pixel(x, y)[c]; }

  // Bilinear sample at continuous pixel coordinates (pixel centres at integer + 0.5),
  // clamped at the border. Writes channels() values to `out`.
  void SampleBilinear(float x, float y, float* out) const;

  // A cv::Mat of type CV_32FC(channels) that shares this image's memory.
  cv::Mat AsMat();
  cv::Mat AsMat() const;  // the caller must not write through it
  // Copies any 1..4 channel Mat (8U, 16U or 32F) into a float image; 8U/16U scaled to [0,1].
  static Image FromMat(const cv::Mat& mat);

  bool operator==(const Image& other) const = default;

 private:
  int width_ = 0, height_ = 0, channels_ = 0;
  std::vector<float> data_;
};

}  // namespace mesocap
