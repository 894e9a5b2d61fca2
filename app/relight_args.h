// mesocap relight: the options, parsed by the front executable (app/main.cc), and the run
// (app/relight_cmd.cc), which the front reaches through the commands module once it is chosen.
#pragma once

#include <string>

namespace CLI {
class App;
}

namespace mesocap::app {

struct RelightArgs {
  std::string ptm;
  std::string light;
  std::string out;
  int bits = 8;
  int threads = -1;
  bool linear = false;  // the PTM holds linear values (fit-ptm --linearize): 8-bit output is sRGB-encoded
};

CLI::App* AddRelightOptions(CLI::App& app, RelightArgs* args);
int RunRelight(const RelightArgs& args);

}  // namespace mesocap::app
