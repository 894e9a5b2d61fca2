// mesocap import: the options, parsed by the front executable (app/main.cc), and the run
// (app/import_cmd.cc), which the front reaches through the commands module once it is chosen.
#pragma once

#include <string>

#include "capture/import.h"

namespace CLI {
class App;
}

namespace mesocap::app {

struct ImportArgs {
  ImportOptions options;
  std::string link = "hardlink";
  bool no_progress = false;
};

CLI::App* AddImportOptions(CLI::App& app, ImportArgs* args);
int RunImport(ImportArgs& a);

}  // namespace mesocap::app
