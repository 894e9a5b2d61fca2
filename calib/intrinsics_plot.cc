#include "calib/intrinsics_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <opencv2/imgproc.hpp>

#include "core/image_io.h"

namespace mesocap {
namespace {

// A distinct colour per image (BGR, 8-bit sRGB): hues spread by the golden angle.
cv::Scalar ImageColour(int k) {
  const double hue = std::fmod(k * 137.508, 360.0);
  cv::Mat hsv(1, 1, CV_8UC3, cv::Scalar(hue / 2, 220, 200)), bgr;
  cv::cvtColor(hsv, bgr, cv::COLOR_HSV2BGR);
  const cv::Vec3b c = bgr.at<cv::Vec3b>(0, 0);
  return cv::Scalar(c[0], c[1], c[2]);
}

void Text(cv::Mat* canvas, const std::string& text, cv::Point at, double scale) {
  cv::putText(*canvas, text, at, cv::FONT_HERSHEY_SIMPLEX, scale, cv::Scalar(40, 40, 40), 1, cv::LINE_AA);
}

std::string Fmt(const char* fmt, double v) {
  char buf[128];
  std::snprintf(buf, sizeof buf, fmt, v);
  return buf;
}

}  // namespace

std::string ResidualPlotOptions::Check() const {
  if (width_px < 200 || width_px > 20000) return "the plot width must be between 200 and 20000 px";
  if (vector_scale < 0) return "the residual magnification must not be negative (0: automatic)";
  return "";
}

Image PlotIntrinsicsResiduals(const IntrinsicsResult& result, const ResidualPlotOptions& options) {
  MESOCAP_CHECK(options.Check().empty(), options.Check());
  const CameraModel& cam = result.camera;
  MESOCAP_CHECK(cam.width > 0 && cam.height > 0, "the result has no camera size");

  // Left panel keeps the camera's aspect ratio; the right panel is a square of the same height.
  const double aspect = double(cam.height) / cam.width;
  const int left_w = std::max(100, int(std::lround(options.width_px / (1.0 + aspect))));
  const int height = std::max(100, int(std::lround(left_w * aspect)));
  const int width = left_w + height;
  cv::Mat canvas(height, width, CV_8UC3, cv::Scalar(255, 255, 255));
  const double font = std::max(0.35, height / 1400.0);
  const int line_h = int(30 * font) + 4;

  std::vector<double> norms;
  for (const auto& im : result.images)
    if (im.used)
      for (const auto& r : im.residuals_px) norms.push_back(r.norm());
  std::sort(norms.begin(), norms.end());
  const double p99 = norms.empty() ? 1.0 : std::max(1e-6, norms[size_t(0.99 * (norms.size() - 1))]);
  const double rms = result.report.rms_reprojection_px;

  // Left: residual vectors over the image frame.
  const int margin = std::max(10, left_w / 40);
  const int top = int(1.5 * line_h);  // room for the title above the frame
  const double s = std::min(double(left_w - 2 * margin) / cam.width, double(height - top - margin) / cam.height);
  const double mag = options.vector_scale > 0 ? options.vector_scale : 0.04 * left_w / (p99 * s);
  const cv::Point2d origin(margin, top);
  cv::rectangle(canvas, origin, origin + cv::Point2d(cam.width * s, cam.height * s), cv::Scalar(160, 160, 160), 1);
  int k = 0;
  for (const auto& im : result.images) {
    if (!im.used) continue;
    const cv::Scalar colour = ImageColour(k++);
    for (size_t j = 0; j < im.residuals_px.size(); ++j) {
      const cv::Point2d p = origin + cv::Point2d(im.corners_px[j].x() * s, im.corners_px[j].y() * s);
      const cv::Point2d q = p + cv::Point2d(im.residuals_px[j].x() * mag * s, im.residuals_px[j].y() * mag * s);
      cv::circle(canvas, p, 1, colour, cv::FILLED, cv::LINE_AA);
      cv::line(canvas, p, q, colour, 1, cv::LINE_AA);
    }
  }
  Text(&canvas, "reprojection residuals (projected - detected) x" + Fmt("%.0f", mag), {margin, line_h}, font);

  // Right: scatter of all residuals, circles at 1x and 3x the RMS.
  const cv::Point2d centre(left_w + height / 2.0, height / 2.0);
  const double extent_px = std::max({3.0 * rms, p99, 1e-3}) * 1.15;
  const double t = (height / 2.0 - margin) / extent_px;
  cv::line(canvas, centre - cv::Point2d(height / 2.0 - margin, 0), centre + cv::Point2d(height / 2.0 - margin, 0),
           cv::Scalar(200, 200, 200), 1);
  cv::line(canvas, centre - cv::Point2d(0, height / 2.0 - margin), centre + cv::Point2d(0, height / 2.0 - margin),
           cv::Scalar(200, 200, 200), 1);
  k = 0;
  for (const auto& im : result.images) {
    if (!im.used) continue;
    const cv::Scalar colour = ImageColour(k++);
    for (const auto& r : im.residuals_px) {
      const cv::Point2d p = centre + cv::Point2d(std::clamp(r.x() * t, -centre.y, centre.y),
                                                 std::clamp(r.y() * t, -centre.y, centre.y));
      cv::circle(canvas, p, 2, colour, cv::FILLED, cv::LINE_AA);
    }
  }
  cv::circle(canvas, centre, int(std::lround(rms * t)), cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  cv::circle(canvas, centre, int(std::lround(3 * rms * t)), cv::Scalar(120, 120, 120), 1, cv::LINE_AA);
  const int right_x = left_w + margin;
  Text(&canvas, "RMS " + Fmt("%.3f px", rms) + " (circles: 1x, 3x)", {right_x, line_h}, font);
  Text(&canvas, "axes: +/-" + Fmt("%.3f px", extent_px), {right_x, 2 * line_h}, font);
  Text(&canvas, std::to_string(result.report.images_used) + " images, " + std::to_string(result.report.corners_used) +
                    " corners",
       {right_x, height - line_h / 2}, font);

  // 8-bit sRGB BGR -> linear RGB floats, the core Image convention.
  cv::Mat rgb;
  cv::cvtColor(canvas, rgb, cv::COLOR_BGR2RGB);
  Image out = Image::FromMat(rgb);
  const auto& linear = SrgbDecodeTable();
  for (size_t i = 0; i < out.size(); ++i) out.data()[i] = linear[std::clamp(int(std::lround(out.data()[i] * 255.0f)), 0, 255)];
  return out;
}

}  // namespace mesocap
