// mesocap: one subcommand per stage.
// Each <verb>_cmd.cc registers its options and runs one library entry point; this file only
// dispatches and turns failures into exit codes.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>

#include "app/commands.h"
#include "core/image_io.h"
#include "core/logging.h"
#include "core/pixel_memory.h"
#include "core/provenance.h"

int main(int argc, char** argv) {
  mesocap::KeepLargeLibraryBuffersInHeap();
  // Results are printed line by line as stages finish; piped into a log or `tee`, stdout would
  // otherwise hold them all until exit.
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  mesocap::SetCommandLine(argc, argv);
  CLI::App app;
  mesocap::app::GlobalOptions globals;
  std::vector<mesocap::app::Command> commands;
  mesocap::app::DefineCommandLine(app, globals, commands);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    // A bad option: one line and exit code 2, like every other usage error.
    std::fprintf(stderr, "mesocap: %s (see --help)\n", e.what());
    return mesocap::app::kExitUsage;
  }
  mesocap::InitLogging(globals.verbosity);
  mesocap::SetMaxImagePixels(int64_t(globals.max_megapixels * 1e6));
  try {
    for (auto& command : commands)
      if (app.got_subcommand(command.name)) return command.run();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "mesocap: internal error: %s\n", e.what());
    return mesocap::app::kExitInternal;
  }
  return mesocap::app::kExitUsage;
}
