// mesocap evaluate: the options, parsed by the front executable (app/main.cc), and the run
// (app/evaluate_cmd.cc), which the front reaches through the commands module once it is chosen.
#pragma once

#include <filesystem>
#include <string>

#include "app/btf_method_args.h"

namespace CLI {
class App;
}

namespace mesocap::app {

struct EvaluateArgs {
  std::string material = "weave";
  std::filesystem::path session;  // a virtual session's calibrated slices instead of the rig's 13 x 81
  std::filesystem::path out;
  int size = 128;
  int pairs = -1;
  int samples_per_axis = 0;  // 0: TruthSamplesPerAxis
  bool pixel_only = false;
  double max_view_extrapolation = 1e9;
  BtfMethodArgs method;
  int threads = -1;
  bool no_progress = false;
};

CLI::App* AddEvaluateOptions(CLI::App& app, EvaluateArgs* args);
int RunEvaluate(EvaluateArgs& a);

}  // namespace mesocap::app
