// mesocap calibrate: the options, parsed by the front executable (app/main.cc), and the run
// (app/calibrate_cmd.cc), which the front reaches through the commands module once it is chosen.
#pragma once

#include <filesystem>

#include "calib/calibrate.h"
#include "calib/resample.h"

namespace CLI {
class App;
}

namespace mesocap::app {

struct CalibrateArgs {
  CalibrateOptions options;
  ResampleOptions resample;
  bool no_resample = false, no_brdf_smoothing = false, no_chroma_detail = false;
  std::filesystem::path camera_file, layout_file;
  bool no_progress = false;
};

CLI::App* AddCalibrateOptions(CLI::App& app, CalibrateArgs* args);
int RunCalibrate(CalibrateArgs& a);

}  // namespace mesocap::app
