// mesocap decorate: a mesh dressed in the material. Loads and repairs the mesh, makes its tangent
// frames (a user field or relaxation), analyses the exemplar's textons, synthesizes the per-vertex
// surface texton map (mesh/surface_textons.h) and writes, all together or not at all:
// surface_map.ply, textons.exr, report.json, previews/light_<k>.png under three lights and gltf/,
// the dressed mesh as a glTF asset (app/dressed_gltf.h).
#include <chrono>
#include <cstdio>

#include "app/commands.h"
#include "app/dressed_gltf.h"
#include "app/material_maps.h"
#include "app/decorate_args.h"
#include "app/surface_views.h"
#include "app/synth_output.h"
#include "core/atomic_file.h"
#include "core/json.h"
#include "core/progress.h"
#include "core/session_layout.h"
#include "core/session.h"
#include "mesh/atlas_bake.h"
#include "mesh/surface_map_file.h"
#include "synth/exemplar.h"

namespace mesocap::app {
namespace {

namespace fs = std::filesystem;
constexpr const char* kVerb = "decorate";
constexpr int kAtlasGutter = 2;  // texels kept around each chart (mipmaps of two levels never mix charts)

StatusOr<TangentFrames> Frames(const DecorateArgs& a, const TriangleMesh& mesh) {
  if (a.field.empty()) return RelaxedFrames(mesh);
  auto field = ReadDirectionField(a.field);
  if (!field.ok()) return field.status();
  MESOCAP_RETURN_IF_ERROR(CheckFieldMatchesMesh(*field, mesh, a.field));
  return FieldFrames(mesh, *field);
}

Json UsageJson(const SurfaceMapUsage& u) {
  return Json{{"repeats", u.repeats}, {"coherent_edges", u.coherent}, {"texels_used", u.texels_used}};
}

}  // namespace

int RunDecorate(DecorateArgs& a) {
  const auto start = std::chrono::steady_clock::now();
  if (!IsMissingOrEmptyDir(a.out)) return Fail(kVerb, a.out.string() + ": exists and is not empty", kExitUsage);
  int preview_w = 0, preview_h = 0;
  if (!ParseSize(a.preview_size, &preview_w, &preview_h))
    return Fail(kVerb, "--preview-size '" + a.preview_size + "' is not WxH", kExitUsage);
  a.texton.seed = a.seed, a.texton.num_threads = a.threads;
  a.texton_analysis.num_threads = a.threads, a.texton_analysis.seed = a.seed;
  if (Status st = a.texton.Check(); !st.ok()) return Fail(kVerb, st.message(), kExitUsage);

  MeshRepairReport repairs;
  auto mesh = LoadMesh(a.mesh, &repairs);
  if (!mesh.ok()) return Fail(kVerb, mesh.status());
  for (const std::string& line : repairs.Lines()) std::fprintf(stderr, "decorate: %s: repaired: %s\n", a.mesh.string().c_str(), line.c_str());
  auto frames = Frames(a, *mesh);
  if (!frames.ok()) return Fail(kVerb, frames.status());

  ExemplarOptions exemplar_options;
  exemplar_options.features = false, exemplar_options.board = a.board, exemplar_options.num_threads = a.threads;
  auto exemplar = LoadExemplar(a.input, exemplar_options);
  if (!exemplar.ok()) return Fail(kVerb, exemplar.status());
  const Exemplar& e = *exemplar;

  StatusOr<TextonAnalysis> analysis = Status::Error("");
  {
    ProgressBar bar("textons", !a.no_progress);
    analysis = AnalyzeTextons(AppearanceImageCount(e), [&](int k) { return AppearanceLuminance(e, k); }, a.texton_analysis,
                              bar.AsCallback());
  }
  if (!analysis.ok()) return Fail(kVerb, analysis.status());
  SurfaceTextonReport report;
  StatusOr<SurfaceMap> map = Status::Error("");
  {
    ProgressBar bar("surface", !a.no_progress);
    map = SurfaceTextonSynthesis(*mesh, *frames, *analysis, a.texton, &report, bar.AsCallback());
  }
  if (!map.ok()) return Fail(kVerb, map.status());
  DressedMesh dressed{std::move(*mesh), std::move(*frames), std::move(*map)};
  const SurfaceMapUsage usage = MeasureSurfaceMap(dressed.mesh, dressed.frames, dressed.map);

  auto staging = StagingFolder::Begin(a.out);
  if (!staging.ok()) return Fail(kVerb, staging.status());
  const DecorateFolder dir{staging->path()};
  if (Status st = WriteDressedMesh(dir.surface_map(), dressed); !st.ok()) return Fail(kVerb, st);
  if (Status st = WriteTextonAnalysis(dir.textons(), *analysis); !st.ok()) return Fail(kVerb, st);

  // The glTF asset: an atlas, the map baked into it, the exemplar's material maps through it.
  const auto gltf_start = std::chrono::steady_clock::now();
  auto atlas = BuildAtlas(dressed.mesh, {a.atlas_size, kAtlasGutter});
  if (!atlas.ok()) return Fail(kVerb, Status::Error(a.mesh.string() + ": " + atlas.status().message()));
  StatusOr<GgxMaterialMaps> material = Status::Error("");
  {
    ProgressBar bar("material", !a.no_progress && e.kind == ExemplarKind::kBtf);
    material = ExemplarMaterialMaps(e, a.board, a.threads, bar.AsCallback());
  }
  if (!material.ok()) return Fail(kVerb, material.status());
  const SynthMap baked = BakeSurfaceMap(dressed.mesh, dressed.frames, dressed.map, *atlas, kAtlasGutter, a.threads);
  fs::create_directories(dir.gltf().root);
  auto gltf = WriteDressedGltf(dir.gltf(), dressed, *atlas, baked, *material);
  if (!gltf.ok()) return Fail(kVerb, gltf.status());
  const double gltf_seconds = SecondsSince(gltf_start);

  const auto previews_start = std::chrono::steady_clock::now();
  auto appearance = SurfaceAppearance::FromExemplar(e);
  if (!appearance.ok()) return Fail(kVerb, appearance.status());
  auto scene = SurfaceScene::Build(dressed.mesh);
  if (!scene.ok()) return Fail(kVerb, scene.status());
  const RenderCamera camera = FramingCamera(dressed.mesh, preview_w, preview_h);
  const std::vector<RenderLight> lights = PreviewLights(camera);
  fs::create_directories(dir.previews());
  Json previews = Json::array();
  for (size_t k = 0; k < lights.size(); ++k) {
    const fs::path file = dir.preview_light(int(k));
    double lit = 0;
    if (Status st = RenderDressedToPng(*scene, *appearance, dressed, camera, lights[k], 1.0, file, a.threads, &lit); !st.ok())
      return Fail(kVerb, st);
    previews.push_back({{"file", fs::relative(file, dir.root).string()}, {"light", lights[k].vector}, {"lit_share", lit}});
  }

  Json levels = Json::array();
  for (const auto& l : report.levels)
    levels.push_back({{"vertices", l.vertices}, {"uncovered_slots", l.uncovered_slots}, {"mean_candidates", l.mean_candidates}});
  Json j = {
      {"method", "texton"},
      {"mesh", {{"file", fs::absolute(a.mesh).string()}, {"vertices", dressed.mesh.vertex_count()},
                {"faces", dressed.mesh.face_count()}, {"repairs", repairs.Lines()}}},
      {"exemplar", {{"file", fs::absolute(a.input).string()}, {"kind", ExemplarKindToString(e.kind)}, {"width", e.width},
                    {"height", e.height}}},
      {"field", a.field.empty() ? Json("relaxed") : Json(fs::absolute(a.field).string())},
      {"options", {{"k", a.texton.k}, {"neighbourhood", a.texton.neighbourhood}, {"passes", a.texton.passes},
                   {"levels", a.texton.levels}, {"texel_size", report.texel_size}, {"seed", a.seed}}},
      {"levels", levels},
      {"quality", UsageJson(usage)},
      {"previews", previews},
      {"gltf", {{"file", fs::relative(dir.gltf().material(), dir.root).string()}, {"atlas_size", gltf->atlas_size},
                {"charts", gltf->charts}, {"atlas_fill", gltf->fill}, {"vertices", gltf->vertices},
                {"index_bits", gltf->wide_indices ? 32 : 16}}},
      {"seconds", {{"analysis", analysis->seconds}, {"pyramid", report.seconds_pyramid}, {"lists", report.seconds_lists},
                   {"templates", report.seconds_templates}, {"synthesis", report.seconds_synthesis},
                   {"gltf", gltf_seconds}, {"previews", SecondsSince(previews_start)}, {"total", SecondsSince(start)}}},
  };
  if (Status st = WriteTextAtomically(dir.report(), j.dump(2) + "\n"); !st.ok()) return Fail(kVerb, st);
  if (Status st = staging->Publish(); !st.ok()) return Fail(kVerb, st);
  std::printf("decorate: %s (%d vertices) dressed in %s (%s, %dx%d) by texton synthesis in %.1f s: %.1f%% of edges inside "
              "patches, %.2f%% repeats -> %s\n",
              a.mesh.string().c_str(), dressed.mesh.vertex_count(), a.input.string().c_str(), ExemplarKindToString(e.kind).c_str(),
              e.width, e.height, report.seconds, 100 * usage.coherent, 100 * usage.repeats, a.out.string().c_str());
  return kExitOk;
}

}  // namespace mesocap::app
