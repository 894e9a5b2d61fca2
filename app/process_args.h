// mesocap process: the options, parsed by the front executable (app/main.cc), and the run
// (app/process_cmd.cc), which the front reaches through the commands module once it is chosen.
#pragma once

#include <filesystem>
#include <string>

#include "app/process.h"

namespace CLI {
class App;
}

namespace mesocap::app {

struct ProcessArgs {
  ProcessOptions options;
  std::string synth_size = "512x512";
  bool no_brdf_smoothing = false, no_chroma_detail = false;
  std::string ptm_format = "rgb";
  std::string shard;  // "I/N"
  std::filesystem::path outcome;  // --outcome FILE
  bool no_progress = false;
};

CLI::App* AddProcessOptions(CLI::App& app, ProcessArgs* args);
int RunProcess(ProcessArgs& a);

}  // namespace mesocap::app
