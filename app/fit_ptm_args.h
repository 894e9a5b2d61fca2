// mesocap fit-ptm: the options, parsed by the front executable (app/main.cc), and the run
// (app/fit_ptm_cmd.cc), which the front reaches through the commands module once it is chosen.
#pragma once

#include <string>

namespace CLI {
class App;
}

namespace mesocap::app {

struct FitPtmArgs {
  std::string lp;
  std::string out;
  std::string format = "lrgb";
  std::string normals;
  std::string albedo;
  bool linearize = false;
  int threads = -1;
  bool no_progress = false;
};

CLI::App* AddFitPtmOptions(CLI::App& app, FitPtmArgs* args);
int RunFitPtm(const FitPtmArgs& args);

}  // namespace mesocap::app
