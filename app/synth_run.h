// The `synth` methods on an exemplar's features, one entry point for `mesocap synth` and the
// synth stage of `mesocap process`.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>

#include "core/json.h"
#include "core/progress.h"
#include "core/status.h"
#include "synth/block_synthesis.h"
#include "synth/exemplar.h"
#include "synth/quilt.h"
#include "synth/roller.h"
#include "synth/synth_map.h"
#include "synth/texton_analysis.h"
#include "synth/texton_synthesis.h"

namespace mesocap::app {

// The methods `synth` and `process --synth` accept: roller, quilt, ptm-block, texton.
bool IsSynthMethod(const std::string& name);

struct SynthMethodOptions {
  std::string method = "quilt";  // roller | quilt | ptm-block | texton
  int width = 512, height = 512;
  uint32_t seed = 1;
  int num_threads = -1;
  RollerOptions roller;  // its size, seed and threads come from the fields above
  QuiltOptions quilt;    // likewise
  BlockSynthesisOptions block;  // likewise
  TextonAnalysisOptions texton_analysis;    // its seed and threads come from the fields above
  TextonSynthesisOptions texton;            // likewise, with the size
  std::filesystem::path textons;            // texton: a saved analysis to reuse (empty: analyse)
  int svd_components = 40;  // reported only: the exemplar's features were made with it
  std::string Check() const;  // empty when valid
};

// Finds the map; `report` receives the method's parameters, derived values and timings (what
// report.json holds), `note` a line for the user when the method had to fall back, `analysis`
// (if given) the texton method's analysis, to be saved beside the map.
StatusOr<SynthMap> RunSynthesisMethod(const Exemplar& exemplar, const SynthMethodOptions& options, Json* report,
                                      std::string* note, const ProgressFn& progress = nullptr,
                                      TextonAnalysis* analysis = nullptr);

// What keeps a texton analysis beside the map (SynthOutputRequest::write_extra): textons.exr,
// which `synth --analysis` reuses; null when there is none. `analysis` must outlive the writer.
std::function<Status(const std::filesystem::path&)> TextonAnalysisWriter(const TextonAnalysis& analysis);

}  // namespace mesocap::app
