#include "app/decorate_run.h"

#include <chrono>
#include <algorithm>
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

// Per vertex, the atlas map's coordinate at the vertex's corner in its first face (what the PLY
// carries for tools that read vertex attributes; renders read the atlas map).
SurfaceMap VertexCoordinates(const TriangleMesh& mesh, const Atlas& atlas, const SynthMap& atlas_map, double texel_size) {
  SurfaceMap map;
  map.method = "quilt", map.sample_width = atlas_map.sample_width, map.sample_height = atlas_map.sample_height;
  map.texel_size = texel_size;
  map.source_x.assign(mesh.vertex_count(), 0.f), map.source_y.assign(mesh.vertex_count(), 0.f), map.label.assign(mesh.vertex_count(), -1);
  std::vector<uint8_t> done(mesh.vertex_count(), 0);
  for (int f = 0; f < mesh.face_count(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int32_t v = mesh.faces[f][k];
      const Eigen::Vector2d& uv = atlas.corner_uv[f][k];
      const int x = std::clamp(int(uv.x()), 0, atlas.size - 1), y = std::clamp(int(uv.y()), 0, atlas.size - 1);
      if (done[v] || !atlas_map.filled(x, y)) continue;
      const size_t i = atlas_map.index(x, y);
      map.source_x[v] = atlas_map.source_x[i], map.source_y[v] = atlas_map.source_y[i], done[v] = 1;
    }
  return map;
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
  if (a.method != "texton" && a.method != "quilt") return Status::Error("unknown surface method '" + a.method + "'");
  MESOCAP_RETURN_IF_ERROR(a.method == "quilt" ? a.quilt.Check(e.width, e.height).WithContext(e.path.string() + ": ") : a.texton.Check());
  MeshRepairReport repairs;
  auto mesh = LoadMesh(a.mesh, &repairs);
  if (!mesh.ok()) return mesh.status();
  auto frames = Frames(a, *mesh);
  if (!frames.ok()) return frames.status();

  // The atlas first: quilting fills its texels, and the glTF asset bakes into it either way.
  const auto atlas_start = std::chrono::steady_clock::now();
  // The mesh's own UVs where they make an atlas, else one made here (said among the repairs).
  std::vector<std::string> repair_lines = repairs.Lines();
  auto atlas = AtlasFromMeshUvs(*mesh, {a.atlas_size, kAtlasGutter});
  const std::string atlas_source = atlas.ok() ? "mesh UVs" : "generated";
  if (!atlas.ok()) {
    if (!mesh->corner_uv.empty())
      repair_lines.push_back("the mesh's UVs are not a usable atlas (" + atlas.status().message() + "): one was generated");
    atlas = BuildAtlas(*mesh, {a.atlas_size, kAtlasGutter});
  }
  if (!atlas.ok()) return atlas.status().WithContext(a.mesh.string() + ": ");
  const AtlasTexels texels = BuildAtlasTexels(*mesh, *atlas, a.threads);
  const double atlas_seconds = SecondsSince(atlas_start);
  DressedMesh dressed{std::move(*mesh), std::move(*frames), {}, {}, {}};
  Json method_figures;
  std::string brief_figures;
  SynthMap baked;
  if (a.method == "quilt") {
    if (e.features.empty()) return Status::Error(e.path.string() + ": the exemplar was loaded without its features");
    SurfaceQuiltReport report;
    StatusOr<SynthMap> quilt = Status::Error("");
    {
      ProgressBar bar("surface", a.progress);
      quilt = SurfaceQuiltSynthesis(dressed.mesh, dressed.frames, *atlas, texels, e.features, a.quilt, &report, bar.AsCallback());
    }
    if (!quilt.ok()) return quilt.status().WithContext(a.mesh.string() + ": ");
    FillAtlasGutter(&*quilt, kAtlasGutter);
    dressed.map = VertexCoordinates(dressed.mesh, *atlas, *quilt, report.texel_size);
    dressed.atlas = *atlas, dressed.atlas_map = std::move(*quilt);
    MESOCAP_RETURN_IF_ERROR(WriteSynthMap(dir.atlas_map(), dressed.atlas_map));
    baked = dressed.atlas_map;
    method_figures = {{"options", {{"patch_radius", report.patch_radius}, {"seam_threshold", a.quilt.seam_threshold},
                                   {"max_area_distortion", a.quilt.max_area_distortion}, {"texel_size", report.texel_size},
                                   {"seed", a.quilt.seed}}},
                      {"quality", {{"texels", report.texels}, {"patches", report.patches},
                                   {"chart_crossing_patches", report.chart_crossing_patches},
                                   {"rejected_cuts", report.rejected_cuts}, {"rejected_flattenings", report.rejected_flattenings},
                                   {"mean_seam_cost", report.sample_neighbour_step > 0 ? report.mean_seam_cost / report.sample_neighbour_step : 0}}},
                      {"seconds", {{"atlas", atlas_seconds}, {"flattening", report.seconds_flattening},
                                   {"matching", report.seconds_matching}, {"cutting", report.seconds_cutting},
                                   {"synthesis", report.seconds}}}};
    char line[256];
    std::snprintf(line, sizeof line, "by graphcut quilting on a %d texel atlas in %.1f s: %d patches, %d across charts",
                  atlas->size, report.seconds, report.patches, report.chart_crossing_patches);
    brief_figures = line;
  } else {
    std::optional<TextonAnalysis> made_here;
    const TextonAnalysis* analysis = a.analysis;  // the caller's, not a copy: shared lists belong to it
    if (!analysis) {
      auto made = AnalyseExemplarTextons(e, a.texton_analysis, a.progress);
      if (!made.ok()) return made.status();
      analysis = &made_here.emplace(std::move(*made));
    }
    SurfaceTextonReport report;
    StatusOr<SurfaceMap> map = Status::Error("");
    {
      ProgressBar bar("surface", a.progress);
      map = SurfaceTextonSynthesis(dressed.mesh, dressed.frames, *analysis, a.texton, &report, bar.AsCallback());
    }
    if (!map.ok()) return map.status().WithContext(a.mesh.string() + ": ");
    dressed.map = std::move(*map);
    const SurfaceMapUsage usage = MeasureSurfaceMap(dressed.mesh, dressed.frames, dressed.map);
    MESOCAP_RETURN_IF_ERROR(WriteTextonAnalysis(dir.textons(), *analysis));
    baked = BakeSurfaceMap(dressed.mesh, dressed.frames, dressed.map, *atlas, texels, kAtlasGutter);
    Json levels = Json::array();
    for (const auto& l : report.levels)
      levels.push_back({{"vertices", l.vertices}, {"uncovered_slots", l.uncovered_slots}, {"mean_candidates", l.mean_candidates}});
    method_figures = {{"options", {{"k", a.texton.k}, {"neighbourhood", a.texton.neighbourhood}, {"passes", a.texton.passes},
                                   {"levels", a.texton.levels}, {"texel_size", report.texel_size}, {"seed", a.texton.seed}}},
                      {"levels", levels},
                      {"quality", UsageJson(usage)},
                      {"seconds", {{"analysis", analysis->seconds}, {"atlas", atlas_seconds}, {"pyramid", report.seconds_pyramid},
                                   {"lists", report.seconds_lists}, {"templates", report.seconds_templates},
                                   {"synthesis", report.seconds_synthesis}}}};
    char line[256];
    std::snprintf(line, sizeof line, "by texton synthesis in %.1f s: %.1f%% of edges inside patches, %.2f%% repeats", report.seconds,
                  100 * usage.coherent, 100 * usage.repeats);
    brief_figures = line;
  }
  MESOCAP_RETURN_IF_ERROR(WriteDressedMesh(dir.surface_map(), dressed));

  // The glTF asset: the map baked into the atlas, the exemplar's material maps through it.
  const auto gltf_start = std::chrono::steady_clock::now();
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

  Json j = {
      {"method", a.method},
      {"mesh", {{"file", fs::absolute(a.mesh).string()}, {"vertices", dressed.mesh.vertex_count()},
                {"faces", dressed.mesh.face_count()}, {"repairs", repair_lines}}},
      {"exemplar", {{"file", fs::absolute(e.path).string()}, {"kind", ExemplarKindToString(e.kind)}, {"width", e.width},
                    {"height", e.height}}},
      {"field", a.field.empty() ? Json("relaxed") : Json(fs::absolute(a.field).string())},
      {"options", method_figures["options"]},
      {"quality", method_figures["quality"]},
      {"previews", previews},
      {"light_sweep", sweep},
      {"gltf", {{"file", fs::relative(dir.gltf().material(), dir.root).string()}, {"atlas", atlas_source}, {"atlas_size", gltf->atlas_size},
                {"charts", gltf->charts}, {"atlas_fill", gltf->fill}, {"vertices", gltf->vertices},
                {"index_bits", gltf->wide_indices ? 32 : 16}}},
      {"seconds", method_figures["seconds"]},
  };
  if (method_figures.contains("levels")) j["levels"] = method_figures["levels"];
  j["seconds"]["gltf"] = gltf_seconds, j["seconds"]["previews"] = SecondsSince(previews_start), j["seconds"]["total"] = SecondsSince(start);
  DecorateResult result;
  result.report = std::move(j);
  result.repairs = repair_lines;
  result.brief = a.mesh.filename().string() + " (" + std::to_string(dressed.mesh.vertex_count()) + " vertices) " + brief_figures;
  MESOCAP_RETURN_IF_ERROR(WriteTextAtomically(dir.report(), result.report.dump(2) + "\n"));
  return result;
}

}  // namespace mesocap::app
