// mesocap synth, synth-apply and paint: the options, parsed by the front executable (app/main.cc), and the run
// (app/synth_cmd.cc), which the front reaches through the commands module once it is chosen.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

#include "synth/block_synthesis.h"
#include "synth/exemplar.h"
#include "synth/quilt.h"
#include "synth/roller.h"
#include "synth/texton_analysis.h"
#include "synth/texton_synthesis.h"

namespace CLI {
class App;
}

namespace mesocap::app {

struct SynthArgs {
  std::string method = "quilt";
  std::filesystem::path input, out, map, feature_mask, target_mask;
  std::string size = "512x512", slices = "all";
  ExemplarOptions exemplar;
  QuiltOptions quilt;
  RollerOptions roller;
  BlockSynthesisOptions block;
  TextonAnalysisOptions texton_analysis;
  TextonSynthesisOptions texton;
  std::filesystem::path analysis;  // texton: a saved textons.exr to reuse
  bool brute_force = false;
  std::string block_basis = "principal";
  PaintOptions paint;
  uint32_t seed = 1;
  int threads = -1;
  bool no_progress = false;
};

// The three commands share one set of options.
using SynthApplyArgs = SynthArgs;
using PaintArgs = SynthArgs;

CLI::App* AddSynthOptions(CLI::App& app, SynthArgs* args);
int RunSynth(SynthArgs& a);
CLI::App* AddSynthApplyOptions(CLI::App& app, SynthArgs* args);
int RunSynthApply(SynthArgs& a);
CLI::App* AddPaintOptions(CLI::App& app, SynthArgs* args);
int RunPaint(SynthArgs& a);

}  // namespace mesocap::app
