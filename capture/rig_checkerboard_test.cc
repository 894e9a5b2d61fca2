// OpenCV's own calibration, run on the rendered checkerboard photographs (written as JPEG and
// read back), must recover the rig's true intrinsics.
#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "capture/rig_render.h"
#include "core/image_io.h"
#include "tests/testing.h"

namespace mesocap {
namespace {

TEST(VirtualRig, CalibrateCameraOnCheckerboardShotsRecoversK) {
  RigOptions o;
  o.shots = 1;
  o.calib_shots = 15;
  o.seed = 3;
  o.width = 1500;
  o.height = 1000;
  auto scene = MakeRigScene(o);
  ASSERT_TRUE(scene.ok());
  auto material = Material::Create("flat");
  ASSERT_TRUE(material.ok());
  RigRenderer renderer(*scene, *material);
  const auto dir = testing::MakeTempDir();
  const RigCheckerboard& cb = scene->checkerboard;
  std::vector<std::vector<cv::Point3f>> object_points;
  std::vector<std::vector<cv::Point2f>> image_points;
  for (int k = 0; k < o.calib_shots; ++k) {
    Image im = renderer.RenderCalibLinear(k);
    renderer.ApplySensor(&im, 1000 + k);
    const auto file = dir / ("calib_" + std::to_string(k) + ".jpg");
    ASSERT_TRUE(WriteImage(file, im).ok());
    auto back = ReadImage(file, {.linearize = false});
    ASSERT_TRUE(back.ok());
    cv::Mat gray8, rgb8;
    back->AsMat().convertTo(rgb8, CV_8UC3, 255.0);
    cv::cvtColor(rgb8, gray8, cv::COLOR_RGB2GRAY);
    std::vector<cv::Point2f> corners;
    ASSERT_TRUE(cv::findChessboardCornersSB(gray8, cv::Size(cb.cols, cb.rows), corners, cv::CALIB_CB_ACCURACY))
        << "shot " << k;
    std::vector<cv::Point3f> obj;
    for (int r = 0; r < cb.rows; ++r)
      for (int c = 0; c < cb.cols; ++c) obj.emplace_back(float(c * cb.square_m), float(r * cb.square_m), 0.0f);
    object_points.push_back(obj);
    image_points.push_back(corners);
  }
  cv::Mat K, dist;
  std::vector<cv::Mat> rvecs, tvecs;
  const double rms = cv::calibrateCamera(object_points, image_points, cv::Size(o.width, o.height), K, dist, rvecs, tvecs);
  const Eigen::Matrix3d& Kt = scene->camera.K;
  std::printf("rms %.3f px; fx %.2f (true %.2f) fy %.2f (true %.2f) cx %.2f (true %.2f) cy %.2f (true %.2f)\n", rms,
              K.at<double>(0, 0), Kt(0, 0), K.at<double>(1, 1), Kt(1, 1), K.at<double>(0, 2), Kt(0, 2),
              K.at<double>(1, 2), Kt(1, 2));
  EXPECT_LT(rms, 0.3);
  EXPECT_NEAR(K.at<double>(0, 0), Kt(0, 0), 0.005 * Kt(0, 0));
  EXPECT_NEAR(K.at<double>(1, 1), Kt(1, 1), 0.005 * Kt(1, 1));
  EXPECT_NEAR(K.at<double>(0, 2), Kt(0, 2), 0.005 * Kt(0, 0));
  EXPECT_NEAR(K.at<double>(1, 2), Kt(1, 2), 0.005 * Kt(1, 1));
}

}  // namespace
}  // namespace mesocap
