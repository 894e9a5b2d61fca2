// Every subcommand in two halves (COLMAP's exe/colmap.cc table, split for start-up): its
// options, declared in app/<verb>_args.h and parsed by the front executable (app/main.cc), and
// its run, in app/<verb>_cmd.cc, inside the commands module (libmesocap_commands.so) that the
// front loads only once a command is chosen. So `mesocap --help` and `--version` map none of
// OpenCV, Ceres or libgphoto2 (issue 14). Exit codes are shared so scripts can trust them.
#pragma once

#include <cstddef>
#include <string>

#include "core/image_io.h"
#include "core/status.h"

namespace mesocap::app {

// 0 success; 1 the work failed on bad data or I/O (message names the file); 2 a bad option;
// 3 interrupted or cancelled; 70 an internal error (a bug). Unknown or missing options are 2 too.
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;
inline constexpr int kExitUsage = 2;
inline constexpr int kExitCancelled = 3;
inline constexpr int kExitInternal = 70;

// Prints "mesocap <verb>: <message>" on stderr and returns `code`.
int Fail(const std::string& verb, const std::string& message, int code = kExitFailure);
// A failed Status: its message, exit 1; a cancelled one (Ctrl-C): says so, exit 3.
int Fail(const std::string& verb, const Status& status);

// Options before the subcommand.
struct GlobalOptions {
  int verbosity = 1;  // 0 quiet, 1 normal, 2 verbose
  double max_megapixels = double(kDefaultMaxImagePixels) / 1e6;
};

// X(Verb) for every subcommand: app/<verb>_args.h declares Verb##Args, Add##Verb##Options and
// Run##Verb. The front defines the options of each, the module runs the chosen one by its name.
#define MESOCAP_FOR_EACH_COMMAND(X)                                                                            \
  X(Simulate) X(Demo) X(Import) X(Capture) X(Console) X(Cameras) X(Calibrate) X(CalibrateCamera) X(FitPtm) X(Relight) \
  X(Reconstruct) X(Evaluate) X(Lights) X(Synth) X(SynthApply) X(Paint) X(Decorate) X(Render) X(Process) X(Export) X(Coverage) \
  X(Layout)

// The commands module's one entry point: runs the command `verb` ("FitPtm") on `args`, the
// Verb##Args the front parsed (`args_size` its size, a check that both halves come from one
// build), after setting up what every command shares from `globals` and the command line.
using RunCommandFn = int (*)(const char* verb, void* args, size_t args_size, const GlobalOptions* globals, int argc,
                             char** argv);
inline constexpr const char* kRunCommandSymbol = "MesocapRunCommand";
inline constexpr const char* kCommandsModuleName = "libmesocap_commands.so";

}  // namespace mesocap::app
