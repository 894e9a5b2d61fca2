// The one image type at the core: float, N interleaved channels, row-major, contiguous.
// Converts to cv::Mat without a copy (the Mat views this image's memory).
#pragma once

#include <cstddef>
#include <cstdint>
#include <new>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

#include "core/pixel_memory.h"

namespace mesocap {

// The allocator of Image's samples: pixel memory, and samples left uninitialised unless a value
// is given (Image::Uninitialized), so a buffer about to be overwritten is not written twice.
template <typename T>
struct PixelAllocator {
  using value_type = T;
  PixelAllocator() = default;
  template <typename U>
  PixelAllocator(const PixelAllocator<U>&) {}  // NOLINT: rebinding
  T* allocate(size_t n) { return static_cast<T*>(AllocatePixelMemory(n * sizeof(T))); }
  void deallocate(T* p, size_t) { FreePixelMemory(p); }
  template <typename U>
  void construct(U* p) {
    ::new (static_cast<void*>(p)) U;  // default-initialised: no zeroing
  }
  template <typename U, typename... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
  template <typename U>
  bool operator==(const PixelAllocator<U>&) const { return true; }
};

// 8-bit samples on pixel memory, not zero-filled: a decoder's or encoder's staging buffer.
using PixelBytes = std::vector<uint8_t, PixelAllocator<uint8_t>>;

class Image {
 public:
  Image() = default;
  Image(int width, int height, int channels, float fill = 0.0f);
  // Samples not initialised: for a producer that writes every one of them.
  static Image Uninitialized(int width, int height, int channels);

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
  std::vector<float, PixelAllocator<float>> data_;
};

// Rec. 709 luminance of a linear RGB(A) image, one channel; an image of fewer than three channels
// gives its first channel.
Image Luminance(const Image& image);

// The mean of each channel over all pixels (zeros for an empty image).
std::vector<double> ChannelMeans(const Image& image);

}  // namespace mesocap
