// mesocap capture: the options, parsed by the front executable (app/main.cc), and the run
// (app/capture_cmd.cc), which the front reaches through the commands module once it is chosen.
#pragma once

#include <string>
#include <vector>

#include "app/capture_guide.h"
#include "capture/tethered_capture.h"

namespace CLI {
class App;
class Option;
}

namespace mesocap::app {

struct CaptureArgs {
  CaptureOptions options;
  std::string camera_model, port, mode = "interval";
  bool show_config = false;
  CLI::Option* shots_option = nullptr;
  bool no_progress = false;
  bool guide = false, follow_guide = false;
  std::vector<std::string> guide_images;  // MirrorImages() names: CoverageOptions::images
  CaptureGuideOptions guidance = [] {
    CaptureGuideOptions o;
    o.coverage.suggestions = 3;
    return o;
  }();
};

CLI::App* AddCaptureOptions(CLI::App& app, CaptureArgs* args);
int RunCapture(CaptureArgs& a);

}  // namespace mesocap::app
