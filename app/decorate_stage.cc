#include "app/decorate_stage.h"

#include <algorithm>
#include <future>
#include <optional>
#include <set>

#include "app/decorate_run.h"
#include "app/synth_stage.h"
#include "core/atomic_file.h"
#include "export/gltf_material.h"

namespace mesocap::app {
namespace fs = std::filesystem;

std::string CheckDecorateMeshes(const std::vector<fs::path>& meshes, const std::vector<std::string>& methods) {
  std::set<std::string> names, seen;
  if (methods.empty()) return "--decorate-method: none given";
  for (const std::string& method : methods) {
    if (method != "texton" && method != "quilt") return "--decorate-method " + method + ": texton or quilt";
    if (!seen.insert(method).second) return "--decorate-method " + method + ": given twice";
  }
  for (const fs::path& m : meshes)
    for (const std::string& method : methods)
      if (!names.insert(DecorateFolderName(m, method)).second)
        return "--decorate: two meshes would share the folder '" + DecorateFolderName(m, method) + "' (mesh names name folders)";
  return "";
}

std::string DecorateFolderName(const fs::path& mesh, const std::string& method) {
  return method == "texton" ? mesh.stem().string() : mesh.stem().string() + "-" + method;
}

StatusOr<StageSummary> RunDecorateStage(const fs::path& session, const DecorateStageOptions& options, int num_threads,
                                        bool progress) {
  const SessionLayout layout(session);
  const bool texton = std::count(options.methods.begin(), options.methods.end(), "texton") > 0;
  const bool quilt = std::count(options.methods.begin(), options.methods.end(), "quilt") > 0;
  auto btf = StageExemplar(session, num_threads, /*features=*/quilt, /*progress=*/false);  // quilting matches features
  if (!btf.ok()) return btf.status();
  Exemplar exemplar = *btf;  // the coarse-grid slices: analysis and rendering read each one
  exemplar.slices.clear();
  for (int k : StageSlices(*btf, options.max_slices)) exemplar.slices.push_back(btf->slices[k]);
  auto material = ReadGltfMaterialTextures(layout.exports().gltf());
  if (!material.ok()) return material.status().WithContext("the export stage's glTF material: ");
  auto staging = StagingFolder::Begin(layout.decorate_root());
  if (!staging.ok()) return staging.status();
  auto appearance = SurfaceAppearance::FromExemplar(exemplar);  // read once, rendered for every mesh
  if (!appearance.ok()) return appearance.status();

  std::vector<std::pair<fs::path, std::string>> jobs;  // (mesh, method) in the report's order
  for (const fs::path& mesh : options.meshes)
    for (const std::string& method : options.methods) jobs.push_back({mesh, method});
  std::optional<TextonAnalysis> analysis;                 // one analysis serves every mesh
  std::optional<std::vector<SampleLevel>> sample_levels;  // and one set of k-coherence lists
  const auto dress = [&](size_t job, bool show_progress) {
    const auto& [mesh, method] = jobs[job];
    DecorateRequest request;
    request.mesh = mesh, request.method = method;
    request.texton.seed = request.quilt.seed = options.seed;
    request.texton.num_threads = request.quilt.num_threads = num_threads;
    request.preview_width = request.preview_height = options.preview_size;
    request.sweep_frames = options.sweep_frames;
    request.atlas_size = options.atlas_size;
    request.threads = num_threads, request.progress = show_progress;
    request.appearance = &*appearance;
    if (method == "texton") request.analysis = &*analysis, request.texton.sample_levels = &*sample_levels;  // made by now
    const DecorateFolder folder{staging->path() / DecorateFolderName(mesh, method)};
    fs::create_directories(folder.root);
    return DecorateInto(folder, request, exemplar, *material);
  };
  std::vector<StatusOr<DecorateResult>> results(jobs.size(), Status::Error("not run"));
  // Quilting places one patch after another and leaves a core idle: the quilts run on a thread of
  // their own while the texton side (analysis, lists, meshes: all parallel) goes on. Their
  // progress bar shows only when they run alone.
  auto quilts = std::async(std::launch::async, [&] {
    for (size_t j = 0; j < jobs.size(); ++j)
      if (jobs[j].second == "quilt") results[j] = dress(j, progress && !texton);
  });
  const Status texton_side = [&]() -> Status {
    if (!texton) return Status::Ok();
    TextonAnalysisOptions analysis_options;
    analysis_options.seed = options.seed, analysis_options.num_threads = num_threads;
    analysis_options.representative_slices = options.representative_slices;
    auto made = AnalyseExemplarTextons(exemplar, analysis_options, progress);
    if (!made.ok()) return made.status().WithContext(layout.btf().index().string() + ": ");
    analysis = std::move(*made);
    const SurfaceTextonOptions o;
    auto levels = MakeSampleLevels(*analysis, o.levels > 0 ? o.levels : int(analysis->levels.size()), o.neighbourhood, o.k, num_threads);
    if (!levels.ok()) return levels.status();
    sample_levels = std::move(*levels);
    for (size_t j = 0; j < jobs.size(); ++j)
      if (jobs[j].second == "texton") results[j] = dress(j, progress);
    return Status::Ok();
  }();
  quilts.get();
  MESOCAP_RETURN_IF_ERROR(texton_side);

  StageSummary summary;
  Json meshes = Json::array();
  for (size_t j = 0; j < jobs.size(); ++j) {
    const auto& [mesh, method] = jobs[j];
    if (!results[j].ok()) return results[j].status();
    const DecorateResult& result = *results[j];
    for (const std::string& line : result.repairs) summary.warnings.push_back(mesh.string() + ": repaired: " + line);
    summary.brief += (summary.brief.empty() ? "" : "; ") + result.brief;
    meshes.push_back({{"name", DecorateFolderName(mesh, method)}, {"file", fs::absolute(mesh).string()}, {"method", method},
                      {"brief", result.brief}});
  }
  MESOCAP_RETURN_IF_ERROR(staging->Publish(/*replace=*/true));
  summary.report = {{"meshes", meshes}, {"slices", exemplar.slices.size()}};
  return summary;
}

}  // namespace mesocap::app
