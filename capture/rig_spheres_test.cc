// The mirror highlight on each ball must sit where reflection geometry puts it: the point whose
// normal bisects the directions to the camera and to the flash (truth.json's light).
#include <gtest/gtest.h>

#include "capture/rig_render.h"

namespace mesocap {
namespace {

// Fixed-point iteration for the specular point on a sphere seen from the origin.
Eigen::Vector3d MirrorPoint(const Eigen::Vector3d& c, double r, const Eigen::Vector3d& light) {
  Eigen::Vector3d n = ((-c).normalized() + (light - c).normalized()).normalized();
  for (int it = 0; it < 100; ++it) {
    const Eigen::Vector3d p = c + r * n;
    n = ((-p).normalized() + (light - p).normalized()).normalized();
  }
  return c + r * n;
}

TEST(VirtualRig, SphereHighlightsSitAtTheMirrorPointWithinOneAndAHalfPixels) {
  RigOptions o;
  o.shots = 4;
  o.calib_shots = 0;
  o.seed = 11;
  auto scene = MakeRigScene(o);
  ASSERT_TRUE(scene.ok());
  auto material = Material::Create(o.material);
  ASSERT_TRUE(material.ok());
  RigRenderer renderer(*scene, *material);
  renderer.Prepare();
  const CameraModel& cam = scene->camera;
  int checked = 0;
  for (int shot = 0; shot < o.shots; ++shot) {
    const Image im = renderer.RenderShotLinear(shot);
    const Eigen::Vector3d light = scene->shots[shot].light_m;
    for (size_t i = 0; i < scene->spheres.size(); ++i) {
      const RigSphere& sp = scene->spheres[i];
      const Eigen::Vector3d p = MirrorPoint(sp.center_m, sp.radius_m, light);
      // No highlight where a board or another ball shadows the mirror point.
      if (renderer.Occluded(p, light, RigRenderer::kSphere, int(i))) {
        std::printf("shot %d ball %zu: mirror point in shadow, skipped\n", shot, i);
        continue;
      }
      const Eigen::Vector2d expected = cam.Project(p);
      // Scan the ball's image: every pixel whose ray hits the sphere.
      const Eigen::Vector2d centre_px = cam.Project(sp.center_m);
      const int reach = int(1.3 * sp.radius_m * cam.K(0, 0) / sp.center_m.z());
      double best = -1;
      Eigen::Vector2i best_px(0, 0);
      for (int y = int(centre_px.y()) - reach; y <= int(centre_px.y()) + reach; ++y)
        for (int x = int(centre_px.x()) - reach; x <= int(centre_px.x()) + reach; ++x) {
          if (x < 0 || y < 0 || x >= cam.width || y >= cam.height) continue;
          const Eigen::Vector3d d = cam.PixelToRay({double(x), double(y)});
          const double b = d.dot(sp.center_m);
          if (b * b - (sp.center_m.squaredNorm() - sp.radius_m * sp.radius_m) < 0) continue;
          const float* px = im.pixel(x, y);
          const double lum = px[0] + px[1] + px[2];
          if (lum > best) {
            best = lum;
            best_px = {x, y};
          }
        }
      // Sub-pixel peak: centroid of the pixels above half the peak next to the brightest one.
      double sw = 0, sx = 0, sy = 0;
      for (int y = best_px.y() - 4; y <= best_px.y() + 4; ++y)
        for (int x = best_px.x() - 4; x <= best_px.x() + 4; ++x) {
          const float* px = im.pixel(x, y);
          const double w = std::max(0.0, double(px[0] + px[1] + px[2]) - 0.5 * best);
          sw += w;
          sx += w * x;
          sy += w * y;
        }
      const Eigen::Vector2d found(sx / sw, sy / sw);
      const double err = (found - expected).norm();
      EXPECT_LT(err, 1.5) << "shot " << shot << " sphere at " << sp.center_m.transpose();
      std::printf("shot %d ball (%.2f,%.2f): highlight %.2f px from the mirror point\n", shot, sp.center_m.x(),
                  sp.center_m.y(), err);
      ++checked;
    }
  }
  EXPECT_GE(checked, o.shots * 4 - 3);
}

}  // namespace
}  // namespace mesocap
