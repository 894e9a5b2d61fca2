// Speed of dressing and rendering a large mesh (issue 50's figures; ratios to Tong 2002's in
// docs/benchmarks.md): surface texton synthesis on a 252k-vertex torus from a 128 x 128 crop of a
// photograph (k = 11), and 1024 x 1024 renders with shadows, each new light timed from shading
// the vertices to the last pixel (the ray-casting scene built once); then graphcut quilting of the
// same torus' 512 x 512 atlas (Zhou 2005 §III) and its per-pixel renders.
// Usage: bench_surface [--threads N] [--vertices-side A B] [--texture NAME] [--crop 128] [--atlas 512]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "core/image_io.h"
#include "mesh/atlas_bake.h"
#include "mesh/surface_quilt.h"
#include "mesh/surface_render.h"
#include "mesh/surface_textons.h"
#include "mesh/mesh_shapes.h"

using namespace mesocap;

namespace {
double Since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}
}  // namespace

int main(int argc, char** argv) {
  int threads = -1, major = 700, minor = 360, crop = 128, k = 11, atlas_size = 512;
  std::string texture = "brick";
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--threads") && i + 1 < argc) threads = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--vertices-side") && i + 2 < argc) major = std::atoi(argv[++i]), minor = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--texture") && i + 1 < argc) texture = argv[++i];
    else if (!std::strcmp(argv[i], "--crop") && i + 1 < argc) crop = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--k") && i + 1 < argc) k = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--atlas") && i + 1 < argc) atlas_size = std::atoi(argv[++i]);
  }
  auto photo = ReadImage(std::filesystem::path(MESOCAP_SOURCE_DIR) / "tests" / "data" / "textures" / (texture + ".png"), {true, 3});
  if (!photo.ok() || photo->width() < crop || photo->height() < crop) return std::fprintf(stderr, "cannot read a %d crop of %s\n", crop, texture.c_str()), 1;
  Image sample(crop, crop, 3);
  for (int y = 0; y < crop; ++y)
    for (int x = 0; x < crop; ++x)
      for (int c = 0; c < 3; ++c) sample.at(x, y, c) = photo->at(x, y, c);
  const Exemplar e = ImageExemplar(sample);
  const TriangleMesh mesh = Torus(major, minor);
  const TangentFrames frames = RelaxedFrames(mesh);

  auto t = std::chrono::steady_clock::now();
  TextonAnalysisOptions ao;
  ao.num_threads = threads;
  auto analysis = AnalyzeTextons(AppearanceImageCount(e), [&](int i) { return AppearanceLuminance(e, i); }, ao);
  if (!analysis.ok()) return 1;
  const double analysis_s = Since(t);
  SurfaceTextonOptions o;
  o.k = k, o.num_threads = threads;
  SurfaceTextonReport report;
  t = std::chrono::steady_clock::now();
  auto map = SurfaceTextonSynthesis(mesh, frames, *analysis, o, &report);
  const double synthesis_s = Since(t);
  if (!map.ok()) return std::fprintf(stderr, "%s\n", map.status().message().c_str()), 1;
  std::printf("surface textons: %d vertices, %dx%d %s, k = %d: analysis %.1f s, synthesis %.1f s (pyramid %.1f, lists %.1f, "
              "templates %.1f, passes %.1f)\n",
              mesh.vertex_count(), crop, crop, texture.c_str(), k, analysis_s, synthesis_s, report.seconds_pyramid,
              report.seconds_lists, report.seconds_templates, report.seconds_synthesis);

  auto appearance = SurfaceAppearance::FromExemplar(e);
  t = std::chrono::steady_clock::now();
  auto scene = SurfaceScene::Build(mesh);
  if (!scene.ok()) return std::fprintf(stderr, "%s\n", scene.status().message().c_str()), 1;
  const double scene_s = Since(t);
  const RenderCamera camera = FramingCamera(mesh, 1024, 1024);
  std::vector<double> per_light;
  for (const Eigen::Vector3d& l : {Eigen::Vector3d(1, 0, 0.2), Eigen::Vector3d(0.3, 0.5, 1), Eigen::Vector3d(-1, 0.4, 0.5)}) {
    RenderLight light;
    light.vector = l.normalized();
    t = std::chrono::steady_clock::now();
    const auto colours = ShadeVertices(*appearance, mesh, frames, *map, camera.eye, light, threads);
    const SurfaceRender r = RenderSurface(*scene, colours, camera, light, threads);
    per_light.push_back(Since(t));
  }
  std::sort(per_light.begin(), per_light.end());
  std::printf("render 1024x1024 with shadows: scene %.2f s once, then per new light %.3f s (median of 3; %.3f-%.3f)\n", scene_s,
              per_light[1], per_light[0], per_light[2]);

  t = std::chrono::steady_clock::now();
  auto atlas = BuildAtlas(mesh, {atlas_size, 2});
  if (!atlas.ok()) return std::fprintf(stderr, "%s\n", atlas.status().message().c_str()), 1;
  const AtlasTexels texels = BuildAtlasTexels(mesh, *atlas, threads);
  const double atlas_s = Since(t);
  SurfaceQuiltOptions qo;
  qo.num_threads = threads;
  SurfaceQuiltReport qr;
  t = std::chrono::steady_clock::now();
  auto quilt = SurfaceQuiltSynthesis(mesh, frames, *atlas, texels, sample, qo, &qr);
  const double quilt_s = Since(t);
  if (!quilt.ok()) return std::fprintf(stderr, "%s\n", quilt.status().message().c_str()), 1;
  FillAtlasGutter(&*quilt, 2);
  std::printf("surface quilt: %dx%d atlas (%d texels, %d charts; made in %.1f s), r_w %d: %.1f s (flattening %.1f, matching %.1f, "
              "cutting %.1f), %d patches, %d cuts and %d flattenings refused\n",
              atlas_size, atlas_size, qr.texels, atlas->charts, atlas_s, qr.patch_radius, quilt_s, qr.seconds_flattening,
              qr.seconds_matching, qr.seconds_cutting, qr.patches, qr.rejected_cuts, qr.rejected_flattenings);
  per_light.clear();
  for (const Eigen::Vector3d& l : {Eigen::Vector3d(1, 0, 0.2), Eigen::Vector3d(0.3, 0.5, 1), Eigen::Vector3d(-1, 0.4, 0.5)}) {
    RenderLight light;
    light.vector = l.normalized();
    t = std::chrono::steady_clock::now();
    const SurfaceRender r = RenderSurface(
        *scene, AtlasShader(*appearance, mesh, frames, *atlas, *quilt, qr.texel_size, camera.eye, light), camera, light, threads);
    per_light.push_back(Since(t));
  }
  std::sort(per_light.begin(), per_light.end());
  std::printf("render 1024x1024 through the atlas map, with shadows: per new light %.3f s (median of 3; %.3f-%.3f)\n", per_light[1],
              per_light[0], per_light[2]);
  return 0;
}
