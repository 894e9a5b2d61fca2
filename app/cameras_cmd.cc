// mesocap cameras: lists the cameras libgphoto2 detects, one "MODEL<TAB>PORT" line each, for
// `mesocap capture --camera MODEL --port PORT`.
#include "app/cameras_args.h"

#include <cstdio>
#include <memory>

#include "app/commands.h"
#include "capture/camera.h"

namespace mesocap::app {

int RunCameras(CamerasArgs&) {
  auto cameras = ListCameras();
  if (!cameras.ok()) return Fail("cameras", cameras.status().message(), kExitFailure);
  if (cameras->empty()) {
    std::fprintf(stderr, "mesocap cameras: no camera detected (connected, switched on, not mounted by another "
                         "program?)\n");
    return kExitOk;
  }
  for (const auto& cam : *cameras) std::printf("%s\t%s\n", cam.model.c_str(), cam.port.c_str());
  return kExitOk;
}
}  // namespace mesocap::app
