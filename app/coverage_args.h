// mesocap coverage: the options, parsed by the front executable (app/main.cc), and the run
// (app/coverage_cmd.cc), which the front reaches through the commands module once it is chosen.
#pragma once

#include <filesystem>
#include <string>

#include "reconstruct/light_coverage.h"

namespace CLI {
class App;
}

namespace mesocap::app {

struct CoverageArgs {
  std::filesystem::path session, out, layout_file;
  std::string objective = "spread";
  bool no_mirror_symmetry = false;  // CoverageOptions::images from the slices' own check, or none
  CoverageOptions options;
};

CLI::App* AddCoverageOptions(CLI::App& app, CoverageArgs* args);
int RunCoverage(CoverageArgs a);

}  // namespace mesocap::app
