// Calibration on real photographs: OpenCV's own stereo sample photos (tests/data/
// opencv_chessboard, from Debian's opencv-doc), two cameras of 13 photos each. The default corner
// refinement must be at least as precise as OpenCV's reference procedure (samples/cpp/
// calibration.cpp: findChessboardCorners, cornerSubPix with an 11x11 half window, then
// calibrateCamera), computed here on the same photos.
#include <gtest/gtest.h>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "calib/intrinsics.h"
#include "core/image_u8_io.h"

namespace mesocap {
namespace {
namespace fs = std::filesystem;

const fs::path kPhotos = fs::path(MESOCAP_SOURCE_DIR) / "tests" / "data" / "opencv_chessboard";

std::vector<fs::path> PhotosOf(const std::string& camera) {
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(kPhotos))
    if (e.path().filename().string().rfind(camera, 0) == 0) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  return files;
}

// The reference procedure's RMS reprojection error (pixels).
double OpenCvReferenceRms(const std::vector<fs::path>& files, cv::Size pattern) {
  std::vector<std::vector<cv::Point2f>> image_points;
  std::vector<std::vector<cv::Point3f>> object_points;
  std::vector<cv::Point3f> board;
  for (int r = 0; r < pattern.height; ++r)
    for (int c = 0; c < pattern.width; ++c) board.emplace_back(float(c), float(r), 0.f);
  cv::Size size;
  for (const fs::path& file : files) {
    auto image = ReadImageU8(file, 1);
    EXPECT_TRUE(image.ok()) << file;
    const cv::Mat gray(image->height(), image->width(), CV_8UC1, image->data());
    size = gray.size();
    std::vector<cv::Point2f> corners;
    if (!cv::findChessboardCorners(gray, pattern, corners,
                                   cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_FAST_CHECK | cv::CALIB_CB_NORMALIZE_IMAGE))
      continue;
    cv::cornerSubPix(gray, corners, cv::Size(11, 11), cv::Size(-1, -1),
                     cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 30, 0.0001));
    image_points.push_back(corners);
    object_points.push_back(board);
  }
  cv::Mat K, dist;
  std::vector<cv::Mat> rvecs, tvecs;
  return cv::calibrateCamera(object_points, image_points, size, K, dist, rvecs, tvecs);
}

TEST(IntrinsicsOnRealPhotos, DefaultIsAtLeastAsPreciseAsOpenCvsReferenceOnBothCameras) {
  for (const std::string camera : {"left", "right"}) {
    const auto files = PhotosOf(camera);
    ASSERT_EQ(files.size(), 13u);
    IntrinsicsOptions options;
    options.cols = 9, options.rows = 6, options.square_m = 0.025;
    auto result = CalibrateIntrinsics(files, options);
    ASSERT_TRUE(result.ok()) << result.status().message();
    const double reference = OpenCvReferenceRms(files, cv::Size(9, 6));
    const double ours = result->report.rms_reprojection_px;
    std::printf("%s: mesocap RMS %.3f px over %d images, OpenCV reference %.3f px\n", camera.c_str(), ours,
                result->report.images_used, reference);
    EXPECT_GE(result->report.images_used, 12) << camera;
    EXPECT_LE(ours, reference) << camera;
    // A focal length consistent with the reference's camera (640x480, fx about 535 px).
    EXPECT_NEAR(result->camera.K(0, 0), 535, 10) << camera;
  }
}

}  // namespace
}  // namespace mesocap
