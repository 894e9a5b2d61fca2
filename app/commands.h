// The table of subcommands (COLMAP's exe/colmap.cc): each entry adds its CLI11 subcommand and
// options, then runs when chosen. Exit codes are shared so scripts can trust them.
#pragma once

#include <CLI/CLI.hpp>

#include <functional>
#include <string>
#include <vector>

#include "core/image_io.h"

namespace mesocap::app {

// 0 success; 1 the work failed on bad data or I/O (message names the file); 2 a bad option;
// 3 interrupted or cancelled; 70 an internal error (a bug). Unknown or missing options are 2 too.
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;
inline constexpr int kExitUsage = 2;
inline constexpr int kExitCancelled = 3;
inline constexpr int kExitInternal = 70;

struct Command {
  std::string name;
  std::function<void(CLI::App&)> setup;
  std::function<int()> run;
};

// Prints "mesocap <verb>: <message>" on stderr and returns `code`.
int Fail(const std::string& verb, const std::string& message, int code = kExitFailure);

std::vector<Command> AllCommands();

// Options before the subcommand.
struct GlobalOptions {
  int verbosity = 1;  // 0 quiet, 1 normal, 2 verbose
  double max_megapixels = double(kDefaultMaxImagePixels) / 1e6;
};

// The whole command line: program name, version flag, global options and every subcommand's
// options.
void DefineCommandLine(CLI::App& app, GlobalOptions& globals, std::vector<Command>& commands);

// One factory per <verb>_cmd.cc.
Command SimulateCommand();
Command DemoCommand();
Command ImportCommand();
Command CaptureCommand();
Command CamerasCommand();
Command CalibrateCameraCommand();
Command CalibrateCommand();
Command FitPtmCommand();
Command RelightCommand();
Command ReconstructCommand();
Command EvaluateCommand();
Command LightsCommand();
Command SynthCommand();
Command SynthApplyCommand();
Command PaintCommand();
Command ProcessCommand();
Command ExportCommand();
Command CoverageCommand();

}  // namespace mesocap::app
