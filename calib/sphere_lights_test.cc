// Sphere-highlight light directions against photos of a shiny sphere rendered analytically here
// (orthographic view, Lambert base plus a sharp Phong lobe about the mirror direction, clipped
// at 1 like a camera): the recovered light must be within 1 degree of the one rendered.
#include "calib/sphere_lights.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "tests/testing.h"

namespace mesocap {
namespace {

constexpr double kPi = std::numbers::pi;

Eigen::Vector3d Direction(double elevation_deg, double azimuth_deg) {
  const double e = elevation_deg * kPi / 180, a = azimuth_deg * kPi / 180;
  return {std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e)};
}

double AngleDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) * 180 / kPi;
}

struct Scene {
  int width = 320, height = 240;
  Eigen::Vector2d centre{161.3, 118.7};  // OpenCV pixel coordinates
  double radius = 80.4;
  double albedo = 0.25, background = 0.04;
  double specular = 4.0, shininess = 400;  // a small highlight, clipped at its top
  double noise = 0.004;
};

// Light direction in RTI's frame (x right, y up the image, z toward the camera); 4x4 samples
// per pixel, so the sphere's edge in the photo and in the mask is anti-aliased.
Image Render(const Scene& s, const Eigen::Vector3d& light, uint32_t seed, Image* mask = nullptr) {
  const Eigen::Vector3d L = light.normalized(), v = Eigen::Vector3d::UnitZ();
  Image out(s.width, s.height, 3);
  if (mask) *mask = Image(s.width, s.height, 1);
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0, s.noise);
  constexpr int k = 4;
  for (int y = 0; y < s.height; ++y)
    for (int x = 0; x < s.width; ++x) {
      double sum = 0, cover = 0;
      for (int j = 0; j < k; ++j)
        for (int i = 0; i < k; ++i) {
          const double sx = x - 0.5 + (i + 0.5) / k, sy = y - 0.5 + (j + 0.5) / k;
          const double nx = (sx - s.centre.x()) / s.radius, ny = -(sy - s.centre.y()) / s.radius;
          const double rho2 = nx * nx + ny * ny;
          if (rho2 > 1) {
            sum += s.background;
            continue;
          }
          cover += 1;
          const Eigen::Vector3d n(nx, ny, std::sqrt(1 - rho2));
          const Eigen::Vector3d mirror = 2 * n.dot(L) * n - L;
          const double diffuse = s.albedo * std::max(0.0, n.dot(L));
          const double spec = n.dot(L) > 0 ? s.specular * std::pow(std::max(0.0, mirror.dot(v)), s.shininess) : 0;
          sum += diffuse + spec;
        }
      const double value = std::clamp(sum / (k * k) + noise(rng), 0.0, 1.0);
      for (int c = 0; c < 3; ++c) out.at(x, y, c) = float(value);
      if (mask) mask->at(x, y) = float(cover / (k * k));
    }
  return out;
}

TEST(SphereLights, CircleFromAntialiasedMaskIsSubpixel) {
  const Scene scene;
  Image mask;
  Render(scene, Direction(60, 0), 1, &mask);
  auto circle = CircleFromMask(mask);
  ASSERT_TRUE(circle.ok()) << circle.status().message();
  EXPECT_NEAR(circle->centre_px.x(), scene.centre.x(), 0.02);
  EXPECT_NEAR(circle->centre_px.y(), scene.centre.y(), 0.02);
  EXPECT_NEAR(circle->radius_px, scene.radius, 0.02);
  // A hard (thresholded) mask still lands within a small fraction of a pixel.
  for (size_t i = 0; i < mask.size(); ++i) mask.data()[i] = mask.data()[i] >= 0.5f ? 1.0f : 0.0f;
  circle = CircleFromMask(mask);
  ASSERT_TRUE(circle.ok());
  EXPECT_NEAR(circle->centre_px.x(), scene.centre.x(), 0.1);
  EXPECT_NEAR(circle->radius_px, scene.radius, 0.1);
}

TEST(SphereLights, MaskThatIsNotADiskIsRejected) {
  Image empty(64, 64, 1);
  EXPECT_FALSE(CircleFromMask(empty).ok());
  Image bar(64, 64, 1);
  for (int y = 20; y < 30; ++y)
    for (int x = 5; x < 60; ++x) bar.at(x, y) = 1;
  auto bad = CircleFromMask(bar);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.status().message().find("round"), std::string::npos) << bad.status().message();
}

TEST(SphereLights, RecoversKnownLightsWithinOneDegree) {
  const Scene scene;
  Image mask;
  Render(scene, Direction(60, 0), 1, &mask);
  auto circle = CircleFromMask(mask);
  ASSERT_TRUE(circle.ok());
  std::mt19937 rng(testing::SeedFromTestName());
  std::uniform_real_distribution<double> jitter(-10, 10);
  double worst = 0;
  int n = 0;
  for (double elevation : {20.0, 35.0, 50.0, 65.0, 80.0, 90.0})
    for (double azimuth : {0.0, 72.0, 144.0, 216.0, 288.0}) {
      if (elevation == 90 && azimuth > 0) continue;
      const Eigen::Vector3d light = Direction(elevation, azimuth + jitter(rng));
      const Image photo = Render(scene, light, uint32_t(rng()));
      const SphereLight found = FindSphereLight(photo, *circle);
      ASSERT_TRUE(found.found) << "elevation " << elevation << ": " << found.why_not;
      const double error = AngleDeg(found.light_dir, light);
      worst = std::max(worst, error);
      ++n;
      EXPECT_LT(error, 1.0) << "elevation " << elevation << " azimuth " << azimuth;
    }
  std::printf("%d lights, worst direction error %.3f deg\n", n, worst);
}

TEST(SphereLights, UnclippedHighlightToo) {
  Scene scene;
  scene.specular = 0.6;  // the peak stays below clipping: the centroid of the excess is used
  scene.shininess = 150;
  Image mask;
  Render(scene, Direction(45, 30), 1, &mask);
  auto circle = CircleFromMask(mask);
  ASSERT_TRUE(circle.ok());
  for (double azimuth : {30.0, 200.0}) {
    const Eigen::Vector3d light = Direction(45, azimuth);
    const SphereLight found = FindSphereLight(Render(scene, light, 7), *circle);
    ASSERT_TRUE(found.found) << found.why_not;
    EXPECT_FALSE(found.saturated);
    EXPECT_LT(AngleDeg(found.light_dir, light), 1.0);
  }
}

TEST(SphereLights, PhotoWithoutHighlightIsRejectedWithAReason) {
  Scene matte;
  matte.specular = 0;  // a diffuse sphere: bright, but no mirror highlight
  Image mask;
  Render(matte, Direction(60, 0), 1, &mask);
  auto circle = CircleFromMask(mask);
  ASSERT_TRUE(circle.ok());
  for (const Eigen::Vector3d& light : {Direction(90, 0), Direction(30, 120)}) {
    const SphereLight found = FindSphereLight(Render(matte, light, 3), *circle);
    EXPECT_FALSE(found.found);
    EXPECT_FALSE(found.why_not.empty());
    std::printf("rejected: %s\n", found.why_not.c_str());
  }
  // Light from behind the sphere: nothing but the dark sphere and the background.
  const SphereLight behind = FindSphereLight(Render(Scene{}, Direction(-90, 0), 4), *circle);
  EXPECT_FALSE(behind.found);
  EXPECT_NE(behind.why_not.find("no highlight"), std::string::npos) << behind.why_not;
}

TEST(SphereLights, LightFromHighlightGeometry) {
  const SphereCircle sphere{{100, 100}, 50};
  // Highlight at the centre: light along the view; halfway up the image: tilted toward +y.
  EXPECT_LT(AngleDeg(LightFromHighlight(sphere, {100, 100}), Eigen::Vector3d::UnitZ()), 1e-9);
  const double s = std::sin(kPi / 8);  // normal 22.5 deg from the view -> light 45 deg
  EXPECT_LT(AngleDeg(LightFromHighlight(sphere, {100, 100 - 50 * s}), Eigen::Vector3d(0, 1, 1)), 1e-9);
  EXPECT_LT(AngleDeg(LightFromHighlight(sphere, {100 + 50 * s, 100}), Eigen::Vector3d(1, 0, 1)), 1e-9);
}

}  // namespace
}  // namespace mesocap
