// Dressing one mesh, as decorate and process's decorate stage share it: load and repair the mesh,
// make its frames and atlas, synthesize the surface map (texton: per vertex, from the exemplar's
// texton analysis; quilt: per atlas texel, from its features), and write into a folder
// (DecorateFolder): the map, the analysis or atlas map, the glTF asset, previews and report.json.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "core/json.h"
#include "core/session_layout.h"
#include "core/status.h"
#include "export/ggx_fit.h"
#include "mesh/surface_quilt.h"
#include "mesh/surface_shading.h"
#include "mesh/surface_textons.h"
#include "synth/exemplar.h"
#include "synth/texton_analysis.h"

namespace mesocap::app {

struct DecorateRequest {
  std::filesystem::path mesh, field;  // field empty: a relaxed field
  std::string method = "texton";      // or "quilt" (the exemplar must carry its features)
  SurfaceTextonOptions texton;
  SurfaceQuiltOptions quilt;
  TextonAnalysisOptions texton_analysis;
  int preview_width = 512, preview_height = 512;
  int sweep_frames = 0;  // previews of a light circling the mesh (the report animates them)
  int atlas_size = 512;
  int threads = -1;
  bool progress = true;
  // The exemplar's texton analysis and its slices read for rendering, when a caller dressing
  // several meshes made them once (else made here).
  const TextonAnalysis* analysis = nullptr;
  const SurfaceAppearance* appearance = nullptr;
};

struct DecorateResult {
  Json report;  // what report.json holds
  std::string brief;
  std::vector<std::string> repairs;  // one line per repair the mesh needed
};

// The exemplar's texton analysis (what DecorateInto makes when not given one).
StatusOr<TextonAnalysis> AnalyseExemplarTextons(const Exemplar& exemplar, const TextonAnalysisOptions& options, bool progress);

// Writes into `dir` (existing and empty: a staging folder the caller publishes). `material`: the
// exemplar's glTF maps (app/material_maps.h). Errors name the mesh or field file.
StatusOr<DecorateResult> DecorateInto(const DecorateFolder& dir, const DecorateRequest& request, const Exemplar& exemplar,
                                      const GgxMaterialMaps& material);

}  // namespace mesocap::app
