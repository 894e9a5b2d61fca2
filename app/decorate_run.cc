#include "app/decorate_run.h"

#include <chrono>
#include <cstdio>
#include <optional>

#include "app/dressed_gltf.h"
#include "app/surface_views.h"
#include "core/atomic_file.h"
#include "core/progress.h"
#include "mesh/atlas_bake.h"
#include "mesh/surface_map_file.h"

namespace mesocap::app {
namespace {

namespace fs = std::filesystem;
constexpr int kAtlasGutter = 2;  // texels kept around each chart (mipmaps of two levels never mix charts)

StatusOr<TangentFrames> Frames(const DecorateRequest& a, const TriangleMesh& mesh) {
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

StatusOr<TextonAnalysis> AnalyseExemplarTextons(const Exemplar& e, const TextonAnalysisOptions& options, bool progress) {
  ProgressBar bar("textons", progress);
  return AnalyzeTextons(AppearanceImageCount(e), [&](int k) { return AppearanceLuminance(e, k); }, options, bar.AsCallback());
}

StatusOr<DecorateResult> DecorateInto(const DecorateFolder& dir, const DecorateRequest& a, const Exemplar& e,
                                      const GgxMaterialMaps& material) {
  const auto start = std::chrono::steady_clock::now();
  MESOCAP_RETURN_IF_ERROR(a.texton.Check());
  MeshRepairReport repairs;
  auto mesh = LoadMesh(a.mesh, &repairs);
  if (!mesh.ok()) return mesh.status();
  auto frames = Frames(a, *mesh);
  if (!frames.ok()) return frames.status();

  auto analysis = a.analysis ? StatusOr<TextonAnalysis>(*a.analysis) : AnalyseExemplarTextons(e, a.texton_analysis, a.progress);
  if (!analysis.ok()) return analysis.status();
  SurfaceTextonReport report;
  StatusOr<SurfaceMap> map = Status::Error("");
  {
    ProgressBar bar("surface", a.progress);
    map = SurfaceTextonSynthesis(*mesh, *frames, *analysis, a.texton, &report, bar.AsCallback());
  }
  if (!map.ok()) return map.status().WithContext(a.mesh.string() + ": ");
  DressedMesh dressed{std::move(*mesh), std::move(*frames), std::move(*map)};
  const SurfaceMapUsage usage = MeasureSurfaceMap(dressed.mesh, dressed.frames, dressed.map);

  MESOCAP_RETURN_IF_ERROR(WriteDressedMesh(dir.surface_map(), dressed));
  MESOCAP_RETURN_IF_ERROR(WriteTextonAnalysis(dir.textons(), *analysis));

  // The glTF asset: an atlas, the map baked into it, the exemplar's material maps through it.
  const auto gltf_start = std::chrono::steady_clock::now();
  auto atlas = BuildAtlas(dressed.mesh, {a.atlas_size, kAtlasGutter});
  if (!atlas.ok()) return atlas.status().WithContext(a.mesh.string() + ": ");
  const AtlasTexels texels = BuildAtlasTexels(dressed.mesh, *atlas, a.threads);
  const SynthMap baked = BakeSurfaceMap(dressed.mesh, dressed.frames, dressed.map, *atlas, texels, kAtlasGutter);
  fs::create_directories(dir.gltf().root);
  auto gltf = WriteDressedGltf(dir.gltf(), dressed, *atlas, baked, material);
  if (!gltf.ok()) return gltf.status();
  const double gltf_seconds = SecondsSince(gltf_start);

  const auto previews_start = std::chrono::steady_clock::now();
  std::optional<SurfaceAppearance> read_here;
  const SurfaceAppearance* appearance = a.appearance;
  if (!appearance) {
    auto read = SurfaceAppearance::FromExemplar(e);
    if (!read.ok()) return read.status();
    appearance = &read_here.emplace(std::move(*read));
  }
  auto scene = SurfaceScene::Build(dressed.mesh);
  if (!scene.ok()) return scene.status();
  const RenderCamera camera = FramingCamera(dressed.mesh, a.preview_width, a.preview_height);
  const std::vector<RenderLight> lights = PreviewLights(camera);
  fs::create_directories(dir.previews());
  Json previews = Json::array();
  for (size_t k = 0; k < lights.size(); ++k) {
    const fs::path file = dir.preview_light(int(k));
    double lit = 0;
    MESOCAP_RETURN_IF_ERROR(RenderDressedToPng(*scene, *appearance, dressed, camera, lights[k], 1.0, file, a.threads, &lit));
    previews.push_back({{"file", fs::relative(file, dir.root).string()}, {"light", lights[k].vector}, {"lit_share", lit}});
  }
  Json sweep = Json::array();
  for (int k = 0; k < a.sweep_frames; ++k) {
    const fs::path file = dir.sweep_frame(k);
    MESOCAP_RETURN_IF_ERROR(RenderDressedToPng(*scene, *appearance, dressed, camera, SweepLight(camera, k, a.sweep_frames), 1.0,
                                               file, a.threads));
    sweep.push_back(fs::relative(file, dir.root).string());
  }

  Json levels = Json::array();
  for (const auto& l : report.levels)
    levels.push_back({{"vertices", l.vertices}, {"uncovered_slots", l.uncovered_slots}, {"mean_candidates", l.mean_candidates}});
  Json j = {
      {"method", "texton"},
      {"mesh", {{"file", fs::absolute(a.mesh).string()}, {"vertices", dressed.mesh.vertex_count()},
                {"faces", dressed.mesh.face_count()}, {"repairs", repairs.Lines()}}},
      {"exemplar", {{"file", fs::absolute(e.path).string()}, {"kind", ExemplarKindToString(e.kind)}, {"width", e.width},
                    {"height", e.height}}},
      {"field", a.field.empty() ? Json("relaxed") : Json(fs::absolute(a.field).string())},
      {"options", {{"k", a.texton.k}, {"neighbourhood", a.texton.neighbourhood}, {"passes", a.texton.passes},
                   {"levels", a.texton.levels}, {"texel_size", report.texel_size}, {"seed", a.texton.seed}}},
      {"levels", levels},
      {"quality", UsageJson(usage)},
      {"previews", previews},
      {"light_sweep", sweep},
      {"gltf", {{"file", fs::relative(dir.gltf().material(), dir.root).string()}, {"atlas_size", gltf->atlas_size},
                {"charts", gltf->charts}, {"atlas_fill", gltf->fill}, {"vertices", gltf->vertices},
                {"index_bits", gltf->wide_indices ? 32 : 16}}},
      {"seconds", {{"analysis", analysis->seconds}, {"pyramid", report.seconds_pyramid}, {"lists", report.seconds_lists},
                   {"templates", report.seconds_templates}, {"synthesis", report.seconds_synthesis},
                   {"gltf", gltf_seconds}, {"previews", SecondsSince(previews_start)}, {"total", SecondsSince(start)}}},
  };
  DecorateResult result;
  result.report = std::move(j);
  result.repairs = repairs.Lines();
  char brief[512];
  std::snprintf(brief, sizeof brief, "%s (%d vertices) by texton synthesis in %.1f s: %.1f%% of edges inside patches, %.2f%% repeats",
                a.mesh.filename().string().c_str(), dressed.mesh.vertex_count(), report.seconds, 100 * usage.coherent,
                100 * usage.repeats);
  result.brief = brief;
  MESOCAP_RETURN_IF_ERROR(WriteTextAtomically(dir.report(), result.report.dump(2) + "\n"));
  return result;
}

}  // namespace mesocap::app
