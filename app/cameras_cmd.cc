// mesocap cameras: lists the cameras libgphoto2 detects, one "MODEL<TAB>PORT" line each, for
// `mesocap capture --camera MODEL --port PORT`.
// Not yet registered: the lead adds CamerasCommand() to app/commands.{h,cc} and this file to
// app/CMakeLists.txt.
#include <cstdio>
#include <memory>

#include "app/commands.h"
#include "capture/camera.h"

namespace mesocap::app {

Command CamerasCommand() {
  Command c;
  c.name = "cameras";
  c.setup = [](CLI::App& app) {
    app.add_subcommand("cameras", "List the cameras libgphoto2 detects (model and port, for capture --camera --port)");
  };
  c.run = []() {
    auto cameras = ListCameras();
    if (!cameras.ok()) return Fail("cameras", cameras.status().message(), kExitFailure);
    if (cameras->empty()) {
      std::fprintf(stderr, "mesocap cameras: no camera detected (connected, switched on, not mounted by another "
                           "program?)\n");
      return kExitOk;
    }
    for (const auto& cam : *cameras) std::printf("%s\t%s\n", cam.model.c_str(), cam.port.c_str());
    return kExitOk;
  };
  return c;
}

}  // namespace mesocap::app
