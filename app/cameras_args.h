// mesocap cameras: the options, parsed by the front executable (app/main.cc), and the run
// (app/cameras_cmd.cc), which the front reaches through the commands module once it is chosen.
#pragma once

namespace CLI {
class App;
}

namespace mesocap::app {

struct CamerasArgs {};  // no options

CLI::App* AddCamerasOptions(CLI::App& app, CamerasArgs* args);
int RunCameras(CamerasArgs&);

}  // namespace mesocap::app
