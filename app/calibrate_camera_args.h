// mesocap calibrate-camera: the options, parsed by the front executable (app/main.cc), and the run
// (app/calibrate_camera_cmd.cc), which the front reaches through the commands module once it is chosen.
#pragma once

#include <filesystem>
#include <string>

#include "calib/intrinsics.h"

namespace CLI {
class App;
}

namespace mesocap::app {

struct CalibrateCameraArgs {
  IntrinsicsOptions options;
  std::filesystem::path images_dir;
  std::string board;  // "COLSxROWS", inner corners
  std::filesystem::path out;
  std::filesystem::path plot;  // empty: beside --out, named <stem>_residuals.png
  std::string loss = "huber";
  std::string refinement = "subpix";
  bool no_plot = false;
  bool no_progress = false;
};

CLI::App* AddCalibrateCameraOptions(CLI::App& app, CalibrateCameraArgs* args);
int RunCalibrateCamera(CalibrateCameraArgs& a);

}  // namespace mesocap::app
