// process --decorate MESH: the session's reconstructed BTF (its coarse-grid slices) dressed onto
// each mesh given, with the export's fitted glTF material for the asset's textures ->
// SESSION/decorate/<mesh name>/ (app/decorate_run.h), the folder swapped in whole.
#pragma once

#include <filesystem>
#include <vector>

#include "app/session_stages.h"

namespace mesocap::app {

struct DecorateStageOptions {
  std::vector<std::filesystem::path> meshes;  // empty: no decorate stage
  // Each mesh is dressed by each method: texton into decorate/<mesh name>/, quilt into
  // decorate/<mesh name>-quilt/.
  std::vector<std::string> methods = {"texton"};
  uint32_t seed = 1;
  int max_slices = 289;   // of the reconstructed BTF: those on the coarse grid first
  int preview_size = 384;
  int sweep_frames = 12;  // the report's light sweep
  int atlas_size = 512;
  int representative_slices = 400;  // n_s of the texton analysis (Tong: 400); the demo takes fewer
};

// Mesh names (their file stems) must differ: each names its folder; methods are texton or quilt,
// each once. "" when all is well, else the problem.
std::string CheckDecorateMeshes(const std::vector<std::filesystem::path>& meshes, const std::vector<std::string>& methods);

// The folder name of a mesh dressed by a method (DecorateStageOptions::methods).
std::string DecorateFolderName(const std::filesystem::path& mesh, const std::string& method);

StatusOr<StageSummary> RunDecorateStage(const std::filesystem::path& session, const DecorateStageOptions& options,
                                        int num_threads, bool progress);

}  // namespace mesocap::app
