// mesocap export: the options, parsed by the front executable (app/main.cc), and the run
// (app/export_cmd.cc), which the front reaches through the commands module once it is chosen.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "app/session_export.h"

namespace CLI {
class App;
}

namespace mesocap::app {

struct ExportArgs {
  std::filesystem::path session, out;
  std::vector<std::string> formats;
  ExportOptions options;
};

CLI::App* AddExportOptions(CLI::App& app, ExportArgs* args);
int RunExport(const ExportArgs& a);

}  // namespace mesocap::app
