// mesocap simulate: the options, parsed by the front executable (app/main.cc), and the run
// (app/simulate_cmd.cc), which the front reaches through the commands module once it is chosen.
#pragma once

#include "capture/btf_render.h"
#include "capture/simulate.h"

namespace CLI {
class App;
}

namespace mesocap::app {

struct SimulateArgs {
  SimulateOptions session;
  bool true_btf = false;
  TrueBtfRequest btf;
  bool no_progress = false;
};

CLI::App* AddSimulateOptions(CLI::App& app, SimulateArgs* args);
int RunSimulate(SimulateArgs& a);

}  // namespace mesocap::app
