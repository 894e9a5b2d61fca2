#include "export/previews.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>

namespace mesocap {

Image Thumbnail(const Image& image, int width) {
  const int height = std::max(1, int(std::lround(double(image.height()) * width / image.width())));
  Image out(width, height, image.channels());
  cv::Mat dst = out.AsMat();
  cv::resize(image.AsMat(), dst, dst.size(), 0, 0, cv::INTER_AREA);
  return out;
}

Image ContactSheet(const std::vector<Image>& images, const std::vector<std::string>& labels, int columns,
                   int thumb_width, int gap) {
  if (images.empty()) return Image(thumb_width, thumb_width, 3, 0.1f);
  int thumb_height = 0;
  std::vector<Image> thumbs;
  for (const Image& im : images) {
    thumbs.push_back(Thumbnail(im, thumb_width));
    thumb_height = std::max(thumb_height, thumbs.back().height());
  }
  const int label_h = labels.empty() ? 0 : 18;
  const int rows = (int(images.size()) + columns - 1) / columns;
  const int cols = std::min(columns, int(images.size()));
  Image sheet(cols * (thumb_width + gap) + gap, rows * (thumb_height + label_h + gap) + gap, 3, 0.02f);
  cv::Mat canvas = sheet.AsMat();
  for (size_t k = 0; k < thumbs.size(); ++k) {
    const int x = gap + int(k % columns) * (thumb_width + gap);
    const int y = gap + int(k / columns) * (thumb_height + label_h + gap);
    cv::Mat src = thumbs[k].AsMat();
    if (src.channels() == 1) cv::cvtColor(src, src, cv::COLOR_GRAY2RGB);
    src.colRange(0, std::min(src.cols, thumb_width)).copyTo(canvas(cv::Rect(x, y, thumb_width, src.rows)));
    if (k < labels.size())
      cv::putText(canvas, labels[k], {x + 2, y + thumb_height + 14}, cv::FONT_HERSHEY_SIMPLEX, 0.42,
                  cv::Scalar(0.9, 0.9, 0.9), 1, cv::LINE_AA);
  }
  return sheet;
}

Image HemispherePlot(const std::vector<Eigen::Vector3d>& directions, int size, const std::string& title) {
  Image plot(size, size, 3, 0.03f);
  cv::Mat canvas = plot.AsMat();
  const cv::Point centre(size / 2, size / 2 + 10);
  const int radius = size / 2 - 30;
  for (int deg : {30, 60, 90}) {
    const int r = int(radius * std::sin(deg * M_PI / 180.0));
    cv::circle(canvas, centre, r, cv::Scalar(0.25, 0.25, 0.25), 1, cv::LINE_AA);
    cv::putText(canvas, std::to_string(deg), centre + cv::Point(r + 2, -2), cv::FONT_HERSHEY_SIMPLEX, 0.35,
                cv::Scalar(0.5, 0.5, 0.5), 1, cv::LINE_AA);
  }
  cv::line(canvas, centre - cv::Point(radius, 0), centre + cv::Point(radius, 0), cv::Scalar(0.2, 0.2, 0.2));
  cv::line(canvas, centre - cv::Point(0, radius), centre + cv::Point(0, radius), cv::Scalar(0.2, 0.2, 0.2));
  for (const auto& d : directions) {
    const Eigen::Vector3d n = d.normalized();
    // Orthographic projection onto the disk: x right, y up.
    const cv::Point p(centre.x + int(std::lround(radius * n.x())), centre.y - int(std::lround(radius * n.y())));
    cv::circle(canvas, p, 4, cv::Scalar(1.0, 0.75, 0.2), cv::FILLED, cv::LINE_AA);
  }
  cv::putText(canvas, title, {10, 20}, cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(0.9, 0.9, 0.9), 1, cv::LINE_AA);
  return plot;
}

float DisplayScale(const Image& linear, double percentile) {
  std::vector<float> values(linear.data(), linear.data() + linear.size());
  if (values.empty()) return 1.0f;
  const size_t k = std::min(values.size() - 1, size_t(percentile * values.size()));
  std::nth_element(values.begin(), values.begin() + k, values.end());
  return values[k] > 0 ? 1.0f / values[k] : 1.0f;
}

namespace {

Image Scaled(Image image, float scale) {
  for (size_t i = 0; i < image.size(); ++i) image.data()[i] = std::clamp(image.data()[i] * scale, 0.0f, 1.0f);
  return image;
}

}  // namespace

Image ExposeForDisplay(const Image& linear, double percentile) {
  return Scaled(linear, DisplayScale(linear, percentile));
}

float CommonDisplayScale(const std::vector<const Image*>& linear, double percentile) {
  float scale = 0;
  for (const Image* image : linear) {
    const float s = DisplayScale(*image, percentile);
    scale = scale == 0 ? s : std::min(scale, s);
  }
  return scale == 0 ? 1.0f : scale;
}

std::vector<Image> ExposeAll(const std::vector<Image>& linear, double percentile) {
  std::vector<const Image*> images;
  for (const Image& image : linear) images.push_back(&image);
  const float scale = CommonDisplayScale(images, percentile);
  std::vector<Image> out;
  for (const Image& image : linear) out.push_back(Scaled(image, scale));
  return out;
}

Image GreyPicture(const Image& map, float gain, int min_width) {
  const int zoom = std::max(1, min_width / std::max(1, map.width()));
  Image picture(zoom * map.width(), zoom * map.height(), 3);
  for (int y = 0; y < picture.height(); ++y)
    for (int x = 0; x < picture.width(); ++x)
      for (int c = 0; c < 3; ++c) picture.at(x, y, c) = std::clamp(gain * map.at(x / zoom, y / zoom, 0), 0.0f, 1.0f);
  return picture;
}

std::vector<Image> ExposeTogether(const std::vector<Image>& linear, double percentile) {
  std::vector<Image> out;
  if (linear.empty()) return out;
  const float scale = DisplayScale(linear.front(), percentile);
  for (const Image& image : linear) out.push_back(Scaled(image, scale));
  return out;
}

}  // namespace mesocap
