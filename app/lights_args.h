// mesocap lights: the options, parsed by the front executable (app/main.cc), and the run
// (app/lights_cmd.cc), which the front reaches through the commands module once it is chosen.
#pragma once

#include <string>

#include "calib/sphere_lights.h"

namespace CLI {
class App;
}

namespace mesocap::app {

struct LightsArgs {
  std::string images;
  std::string sphere_mask;
  std::string sphere;  // x,y,r
  std::string out;     // default IMAGES/lights.lp
  SphereLightsOptions options;
};

CLI::App* AddLightsOptions(CLI::App& app, LightsArgs* args);
int RunLights(const LightsArgs& a);

}  // namespace mesocap::app
