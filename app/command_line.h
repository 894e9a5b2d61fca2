// The front executable's whole command line: program name, version flag, global options and
// every subcommand's options (app/commands.h).
#pragma once

#include <memory>
#include <vector>

#include <CLI/CLI.hpp>

#include "app/commands.h"

namespace mesocap::app {

// One subcommand as the front holds it until the module runs it.
struct CommandOptions {
  const char* verb = nullptr;  // "FitPtm": the name the module runs it by
  CLI::App* subcommand = nullptr;
  std::shared_ptr<void> args;  // its Verb##Args, filled by parsing
  size_t args_size = 0;
};

void DefineCommandLine(CLI::App& app, GlobalOptions* globals, std::vector<CommandOptions>* commands);

}  // namespace mesocap::app
