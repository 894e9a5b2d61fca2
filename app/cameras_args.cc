#include "app/cameras_args.h"

#include <CLI/CLI.hpp>

namespace mesocap::app {

CLI::App* AddCamerasOptions(CLI::App& app, CamerasArgs*) {
  return app.add_subcommand("cameras", "List the cameras libgphoto2 detects (model and port, for capture --camera --port)");
}

}  // namespace mesocap::app
