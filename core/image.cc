#include "core/image.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>


#include "core/status.h"

namespace mesocap {

Image Image::Uninitialized(int width, int height, int channels) {
  MESOCAP_CHECK(width >= 0 && height >= 0 && channels > 0, "bad image shape");
  Image image;
  image.width_ = width;
  image.height_ = height;
  image.channels_ = channels;
  image.data_.resize(size_t(width) * height * channels);
  return image;
}

Image::Image(int width, int height, int channels, float fill)
    : width_(width), height_(height), channels_(channels) {
  MESOCAP_CHECK(width >= 0 && height >= 0 && channels > 0, "bad image shape");
  data_.assign(size_t(width) * height * channels, fill);
}

void Image::SampleBilinear(float x, float y, float* out) const {
  const float fx = std::clamp(x - 0.5f, 0.0f, float(width_ - 1));
  const float fy = std::clamp(y - 0.5f, 0.0f, float(height_ - 1));
  const int x0 = std::min(int(fx), width_ - 1), y0 = std::min(int(fy), height_ - 1);
  const int x1 = std::min(x0 + 1, width_ - 1), y1 = std::min(y0 + 1, height_ - 1);
  const float ax = fx - x0, ay = fy - y0;
  const float *p00 = pixel(x0, y0), *p10 = pixel(x1, y0), *p01 = pixel(x0, y1), *p11 = pixel(x1, y1);
  for (int c = 0; c < channels_; ++c) {
    const float top = p00[c] + ax * (p10[c] - p00[c]);
    const float bottom = p01[c] + ax * (p11[c] - p01[c]);
    out[c] = top + ay * (bottom - top);
  }
}

cv::Mat Image::AsMat() { return cv::Mat(height_, width_, CV_32FC(channels_), data_.data()); }

cv::Mat Image::AsMat() const {
  return cv::Mat(height_, width_, CV_32FC(channels_), const_cast<float*>(data_.data()));
}

Image Image::FromMat(const cv::Mat& mat) {
  Image image(mat.cols, mat.rows, mat.channels());
  double scale = 1.0;
  if (mat.depth() == CV_8U) scale = 1.0 / 255.0;
  if (mat.depth() == CV_16U) scale = 1.0 / 65535.0;
  mat.convertTo(image.AsMat(), CV_32FC(mat.channels()), scale);
  return image;
}

Image Luminance(const Image& image) {
  const int channels = image.channels();
  Image out = Image::Uninitialized(image.width(), image.height(), 1);
  for (size_t t = 0; t < image.pixel_count(); ++t) {
    const float* p = image.data() + t * channels;
    out.data()[t] = channels >= 3 ? 0.2126f * p[0] + 0.7152f * p[1] + 0.0722f * p[2] : p[0];
  }
  return out;
}

std::vector<double> ChannelMeans(const Image& image) {
  std::vector<double> mean(image.channels(), 0.0);
  for (size_t i = 0; i < image.pixel_count(); ++i)
    for (int c = 0; c < image.channels(); ++c) mean[c] += image.data()[i * image.channels() + c];
  if (image.pixel_count() > 0)
    for (double& m : mean) m /= double(image.pixel_count());
  return mean;
}

}  // namespace mesocap
