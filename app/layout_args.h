// mesocap layout: the options, parsed by the front executable (app/main.cc), and the run
// (app/layout_cmd.cc), which the front reaches through the commands module once it is chosen.
#pragma once

#include <string>

namespace CLI {
class App;
}

namespace mesocap::app {

struct LayoutArgs {
  std::string session;
  bool json = false;
};

CLI::App* AddLayoutOptions(CLI::App& app, LayoutArgs* args);
int RunLayout(const LayoutArgs& args);

}  // namespace mesocap::app
