// mesocap demo: the options, parsed by the front executable (app/main.cc), and the run
// (app/demo_cmd.cc), which the front reaches through the commands module once it is chosen.
#pragma once

#include <filesystem>

#include "capture/simulate.h"

namespace CLI {
class App;
}

namespace mesocap::app {

struct DemoArgs {
  SimulateOptions simulate = [] {
    SimulateOptions o;
    o.rig.shots = 24;  // a demo in a minute (issue 14)
    return o;
  }();
  std::filesystem::path out = "mesocap-demo";
  bool no_progress = false;
};

CLI::App* AddDemoOptions(CLI::App& app, DemoArgs* args);
int RunDemo(DemoArgs& a);

}  // namespace mesocap::app
