// mesocap console: the options, parsed by the front executable (app/main.cc), and the run
// (app/console_cmd.cc), which the front reaches through the commands module once it is chosen.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "app/capture_args.h"

namespace CLI {
class App;
}

namespace mesocap::app {

struct ConsoleArgs {
  std::filesystem::path session;
  std::string camera_model, port;
  std::vector<std::string> settings;  // capture's --set
  bool resume = false, review = false;
  std::string mode = "enter";         // enter: the page's button fires the camera; remote: its own release
  std::string listen = "127.0.0.1:8765";
  std::string token;
  int threads = 256;
  bool no_guide = false, follow_guide = false;
  std::vector<std::string> guide_images;
  std::string process_args;  // for finish: `mesocap process SESSION ARGS`
  bool exit_after_finish = false;
  CaptureGuideOptions guidance = OperatorGuidance();
};

CLI::App* AddConsoleOptions(CLI::App& app, ConsoleArgs* args);
int RunConsole(ConsoleArgs& a);

}  // namespace mesocap::app
