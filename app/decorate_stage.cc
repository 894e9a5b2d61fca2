#include "app/decorate_stage.h"

#include <set>

#include "app/decorate_run.h"
#include "app/synth_stage.h"
#include "core/atomic_file.h"
#include "export/gltf_material.h"

namespace mesocap::app {
namespace fs = std::filesystem;

std::string CheckDecorateMeshes(const std::vector<fs::path>& meshes) {
  std::set<std::string> names;
  for (const fs::path& m : meshes)
    if (!names.insert(m.stem().string()).second) return "--decorate: two meshes named '" + m.stem().string() + "' (each names its folder)";
  return "";
}

StatusOr<StageSummary> RunDecorateStage(const fs::path& session, const DecorateStageOptions& options, int num_threads,
                                        bool progress) {
  const SessionLayout layout(session);
  auto btf = StageExemplar(session, num_threads, /*features=*/false, /*progress=*/false);
  if (!btf.ok()) return btf.status();
  Exemplar exemplar = *btf;  // the coarse-grid slices: analysis and rendering read each one
  exemplar.slices.clear();
  for (int k : StageSlices(*btf, options.max_slices)) exemplar.slices.push_back(btf->slices[k]);
  auto material = ReadGltfMaterialTextures(layout.exports().gltf());
  if (!material.ok()) return material.status().WithContext("the export stage's glTF material: ");
  auto staging = StagingFolder::Begin(layout.decorate_root());
  if (!staging.ok()) return staging.status();
  TextonAnalysisOptions analysis_options;  // one analysis serves every mesh
  analysis_options.seed = options.seed, analysis_options.num_threads = num_threads;
  analysis_options.representative_slices = options.representative_slices;
  auto analysis = AnalyseExemplarTextons(exemplar, analysis_options, progress);
  if (!analysis.ok()) return analysis.status().WithContext(layout.btf().index().string() + ": ");
  auto appearance = SurfaceAppearance::FromExemplar(exemplar);  // read once, rendered for every mesh
  if (!appearance.ok()) return appearance.status();
  StageSummary summary;
  Json meshes = Json::array();
  for (const fs::path& mesh : options.meshes) {
    DecorateRequest request;
    request.mesh = mesh;
    request.texton.seed = options.seed, request.texton.num_threads = num_threads;
    request.preview_width = request.preview_height = options.preview_size;
    request.sweep_frames = options.sweep_frames;
    request.atlas_size = options.atlas_size;
    request.threads = num_threads, request.progress = progress;
    request.analysis = &*analysis, request.appearance = &*appearance;
    const DecorateFolder folder{staging->path() / mesh.stem()};
    fs::create_directories(folder.root);
    auto result = DecorateInto(folder, request, exemplar, *material);
    if (!result.ok()) return result.status();
    for (const std::string& line : result->repairs) summary.warnings.push_back(mesh.string() + ": repaired: " + line);
    summary.brief += (summary.brief.empty() ? "" : "; ") + result->brief;
    meshes.push_back({{"name", mesh.stem().string()}, {"file", fs::absolute(mesh).string()}, {"brief", result->brief}});
  }
  MESOCAP_RETURN_IF_ERROR(staging->Publish(/*replace=*/true));
  summary.report = {{"meshes", meshes}, {"slices", exemplar.slices.size()}};
  return summary;
}

}  // namespace mesocap::app
