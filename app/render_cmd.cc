// mesocap render: a dressed mesh (decorate's output) under a light, with cast shadows; one PNG,
// or frames of a turntable or a light sweep.
#include <cmath>
#include <cstdio>

#include "app/commands.h"
#include "app/decorate_args.h"
#include "app/surface_views.h"
#include "app/synth_output.h"
#include "core/progress.h"
#include "core/session_layout.h"
#include "mesh/surface_map_file.h"
#include "synth/exemplar.h"

namespace mesocap::app {
namespace {

namespace fs = std::filesystem;
constexpr const char* kVerb = "render";

// The given mesh must be the one the map dresses (after the same repairs).
Status CheckSameMesh(const fs::path& path, const TriangleMesh& dressed) {
  auto mesh = LoadMesh(path);
  if (!mesh.ok()) return mesh.status();
  if (mesh->vertex_count() != dressed.vertex_count() || mesh->face_count() != dressed.face_count())
    return Status::Error(path.string() + ": not the mesh the map dresses (" + std::to_string(mesh->vertex_count()) + " vertices, the map has " +
                         std::to_string(dressed.vertex_count()) + ")");
  const double tolerance = 1e-5 * BoundingDiagonal(dressed);
  for (int v = 0; v < mesh->vertex_count(); ++v)
    if ((mesh->positions[v] - dressed.positions[v]).norm() > tolerance)
      return Status::Error(path.string() + ": not the mesh the map dresses (vertex " + std::to_string(v) + " moved)");
  return Status::Ok();
}

fs::path FramePath(const fs::path& out, int k) {
  char suffix[32];
  std::snprintf(suffix, sizeof suffix, "_%04d", k);
  return out.parent_path() / (out.stem().string() + suffix + out.extension().string());
}

}  // namespace

int RunRender(RenderArgs& a) {
  int width = 0, height = 0;
  if (!ParseSize(a.size, &width, &height)) return Fail(kVerb, "--size '" + a.size + "' is not WxH", kExitUsage);
  if (a.turntable < 0 || a.light_sweep < 0 || (a.turntable > 0 && a.light_sweep > 0))
    return Fail(kVerb, "--turntable and --light-sweep take a positive frame count, one of them at a time", kExitUsage);
  if (!(a.exposure > 0)) return Fail(kVerb, "--exposure must be positive", kExitUsage);
  const DecorateFolder map_folder{a.map};
  if (std::error_code ec; !fs::is_regular_file(map_folder.surface_map(), ec))
    return Fail(kVerb, a.map.string() + ": no " + map_folder.surface_map().filename().string() +
                           ": not a folder mesocap decorate wrote (--map takes decorate's --out)");
  auto dressed = ReadDressedMesh(map_folder.surface_map());
  if (!dressed.ok()) return Fail(kVerb, dressed.status());
  if (dressed->has_atlas()) {  // a quilt: its per-texel map beside the mesh
    auto atlas_map = ReadSynthMap(map_folder.atlas_map(), /*all_filled=*/false);
    if (!atlas_map.ok()) return Fail(kVerb, atlas_map.status());
    if (atlas_map->width != dressed->atlas.size || atlas_map->height != dressed->atlas.size ||
        atlas_map->sample_width != dressed->map.sample_width || atlas_map->sample_height != dressed->map.sample_height)
      return Fail(kVerb, map_folder.atlas_map().string() + ": does not match " + map_folder.surface_map().filename().string() +
                             " (atlas or sample size)");
    dressed->atlas_map = std::move(*atlas_map);
  }
  if (!a.mesh.empty())
    if (Status st = CheckSameMesh(a.mesh, dressed->mesh); !st.ok()) return Fail(kVerb, st);
  ExemplarOptions exemplar_options;
  exemplar_options.features = false, exemplar_options.board = a.board, exemplar_options.num_threads = a.threads;
  auto exemplar = LoadExemplar(a.input, exemplar_options);
  if (!exemplar.ok()) return Fail(kVerb, exemplar.status());
  if (exemplar->width != dressed->map.sample_width || exemplar->height != dressed->map.sample_height)
    return Fail(kVerb, a.input.string() + ": a " + std::to_string(exemplar->width) + "x" + std::to_string(exemplar->height) +
                           " exemplar, but the map indexes a " + std::to_string(dressed->map.sample_width) + "x" +
                           std::to_string(dressed->map.sample_height) + " sample: not the exemplar decorate used");
  auto appearance = SurfaceAppearance::FromExemplar(*exemplar);
  if (!appearance.ok()) return Fail(kVerb, appearance.status());
  auto scene = SurfaceScene::Build(dressed->mesh);
  if (!scene.ok()) return Fail(kVerb, scene.status());

  RenderCamera camera = FramingCamera(dressed->mesh, width, height);
  if (!a.view.empty()) camera.eye = Eigen::Vector3d(a.view[0], a.view[1], a.view[2]);
  if ((camera.eye - camera.target).norm() <= 0) return Fail(kVerb, "--view is the mesh's centre: the camera needs a direction", kExitUsage);
  RenderLight light = PreviewLights(camera)[0];
  if (!a.light.empty()) light.vector = Eigen::Vector3d(a.light[0], a.light[1], a.light[2]);
  if (!a.light_pos.empty()) light.point = true, light.vector = Eigen::Vector3d(a.light_pos[0], a.light_pos[1], a.light_pos[2]);
  if (!light.point && !(light.vector.norm() > 0)) return Fail(kVerb, "--light must be a non-zero direction", kExitUsage);

  if (a.out.has_parent_path()) {
    std::error_code error;
    fs::create_directories(a.out.parent_path(), error);
    if (error) return Fail(kVerb, a.out.parent_path().string() + ": cannot make the folder (" + error.message() + ")");
  }
  const int frames = std::max({1, a.turntable, a.light_sweep});
  ProgressBar bar("frames", !a.no_progress && frames > 1);
  const Eigen::Vector3d offset = camera.eye - camera.target;
  for (int k = 0; k < frames; ++k) {
    RenderCamera c = camera;
    RenderLight l = light;
    if (a.turntable > 0) {  // the camera turns about the vertical through the centre
      const double angle = 2 * M_PI * k / frames;
      c.eye = camera.target + Eigen::Vector3d(std::cos(angle) * offset.x() + std::sin(angle) * offset.z(), offset.y(),
                                              -std::sin(angle) * offset.x() + std::cos(angle) * offset.z());
    }
    if (a.light_sweep > 0) l = SweepLight(camera, k, frames);
    const fs::path path = frames > 1 ? FramePath(a.out, k) : a.out;
    if (Status st = RenderDressedToPng(*scene, *appearance, *dressed, c, l, a.exposure, path, a.threads); !st.ok())
      return Fail(kVerb, st);
    if (!bar.Update(k + 1, frames, "frame")) return Fail(kVerb, Status::Cancelled());
  }
  std::printf("render: %d frame%s of %dx%d -> %s\n", frames, frames > 1 ? "s" : "", width, height,
              (frames > 1 ? FramePath(a.out, 0).string() + " ..." : a.out.string()).c_str());
  return kExitOk;
}

}  // namespace mesocap::app
