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

// Guidance for an operator during capture: the first three suggestions listed.
inline CaptureGuideOptions OperatorGuidance() {
  CaptureGuideOptions o;
  o.coverage.suggestions = 3;
  return o;
}

struct CaptureArgs {
  CaptureOptions options;
  std::string camera_model, port, mode = "interval";
  bool show_config = false;
  CLI::Option* shots_option = nullptr;
  bool no_progress = false;
  bool guide = false, follow_guide = false;
  std::vector<std::string> guide_images;  // MirrorImages() names: CoverageOptions::images
  CaptureGuideOptions guidance = OperatorGuidance();
};

CLI::App* AddCaptureOptions(CLI::App& app, CaptureArgs* args);
// The guidance's options (--layout, --camera-file, --guide-after, --suggest, --guide-images), as
// `capture --guide` and `console` take them.
void AddGuidanceOptions(CLI::App* sub, CaptureGuideOptions* guidance, std::vector<std::string>* guide_images);
int RunCapture(CaptureArgs& a);

}  // namespace mesocap::app
