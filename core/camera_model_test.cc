#include "core/camera_model.h"

#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>

#include <random>

#include "tests/testing.h"

namespace mesocap {
namespace {

CameraModel TestCamera() {
  CameraModel c;
  c.width = 3000;
  c.height = 2000;
  c.K << 3600, 0, 1496.3, 0, 3601, 1003.8, 0, 0, 1;
  c.dist = {-0.09, 0.06, 0.0007, -0.0004, -0.01};
  return c;
}

TEST(CameraModel, ProjectMatchesOpenCV) {
  const CameraModel cam = TestCamera();
  std::mt19937 rng(testing::SeedFromTestName());
  std::uniform_real_distribution<double> u(-0.35, 0.35), z(0.8, 1.2);
  std::vector<cv::Point3d> points;
  for (int i = 0; i < 200; ++i) points.emplace_back(u(rng), u(rng) * 0.7, z(rng));
  cv::Mat K(3, 3, CV_64F), dist(1, 5, CV_64F);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) K.at<double>(r, c) = cam.K(r, c);
  for (int i = 0; i < 5; ++i) dist.at<double>(i) = cam.dist[i];
  std::vector<cv::Point2d> expected;
  cv::projectPoints(points, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), K, dist, expected);
  for (size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector2d px = cam.Project({points[i].x, points[i].y, points[i].z});
    EXPECT_NEAR(px.x(), expected[i].x, 1e-6);
    EXPECT_NEAR(px.y(), expected[i].y, 1e-6);
  }
}

TEST(CameraModel, PixelToRayInvertsProjectAcrossTheFrame) {
  const CameraModel cam = TestCamera();
  for (double y = 0; y <= cam.height; y += 250)
    for (double x = 0; x <= cam.width; x += 250) {
      const Eigen::Vector3d ray = cam.PixelToRay({x, y});
      EXPECT_NEAR(ray.norm(), 1.0, 1e-12);
      const Eigen::Vector2d back = cam.Project(ray);
      EXPECT_NEAR(back.x(), x, 1e-6);
      EXPECT_NEAR(back.y(), y, 1e-6);
    }
}

TEST(CameraModel, JsonRoundTrip) {
  const CameraModel cam = TestCamera();
  const CameraModel back = CameraModel::FromJson(cam.ToJson());
  EXPECT_EQ(back.K, cam.K);
  EXPECT_EQ(back.dist, cam.dist);
  EXPECT_EQ(back.width, cam.width);
}

}  // namespace
}  // namespace mesocap
