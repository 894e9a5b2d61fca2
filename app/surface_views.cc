#include "app/surface_views.h"

#include <cmath>

#include "core/image_io.h"

namespace mesocap::app {

std::vector<RenderLight> PreviewLights(const RenderCamera& camera) {
  const CameraFrame frame = camera.Frame();
  const Eigen::Vector3d &right = frame.right, &up = frame.up, back = -frame.forward;
  std::vector<RenderLight> lights(3);
  lights[0].vector = (-0.5 * right + 0.6 * up + 0.6 * back).normalized();
  lights[1].vector = back;
  lights[2].vector = (0.9 * right + 0.1 * up + 0.3 * back).normalized();
  return lights;
}

RenderLight SweepLight(const RenderCamera& camera, int k, int n) {
  const CameraFrame frame = camera.Frame();
  const Eigen::Vector3d &right = frame.right, &up = frame.up, back = -frame.forward;
  const double a = 2 * M_PI * k / std::max(1, n);
  RenderLight light;
  light.vector = (std::cos(a) * std::sqrt(0.5) * right + std::sin(a) * std::sqrt(0.5) * up + std::sqrt(0.5) * back).normalized();
  return light;
}

Status RenderDressedToPng(const SurfaceScene& scene, const SurfaceAppearance& appearance, const DressedMesh& d,
                          const RenderCamera& camera, const RenderLight& light, double exposure,
                          const std::filesystem::path& path, int num_threads, double* lit_share) {
  const SurfaceRender r =
      d.has_atlas()
          ? RenderSurface(scene, AtlasShader(appearance, d.mesh, d.frames, d.atlas, d.atlas_map, d.map.texel_size, camera.eye, light),
                          camera, light, num_threads)
          : RenderSurface(scene, ShadeVertices(appearance, d.mesh, d.frames, d.map, camera.eye, light, num_threads), camera, light,
                          num_threads);
  if (lit_share) {
    long surface = 0, lit = 0;
    for (size_t i = 0; i < r.lit.size(); ++i) surface += r.triangle[i] >= 0, lit += r.lit[i];
    *lit_share = surface ? double(lit) / surface : 0;
  }
  ImageWriteOptions options;
  options.format = PixelFormat::kUint8Srgb;
  return WriteImage(path, ToDisplay(r.colour, exposure), options);
}

}  // namespace mesocap::app
