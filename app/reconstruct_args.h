// mesocap reconstruct: the options, parsed by the front executable (app/main.cc), and the run
// (app/reconstruct_cmd.cc), which the front reaches through the commands module once it is chosen.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "app/btf_method_args.h"
#include "reconstruct/slice_set.h"

namespace CLI {
class App;
}

namespace mesocap::app {

struct ReconstructArgs {
  std::filesystem::path session, index, out;
  SliceSetOptions options;
  std::vector<std::string> pairs;  // "theta_i,phi_i,theta_o,phi_o"
  std::string grid = "bonn";
  bool pixel_only = false;
  BtfMethodArgs method;
  bool no_progress = false;
};

CLI::App* AddReconstructOptions(CLI::App& app, ReconstructArgs* args);
int RunReconstruct(ReconstructArgs& a);

}  // namespace mesocap::app
