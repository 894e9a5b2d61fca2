// mesocap: one executable, one subcommand per stage. Each <verb>_cmd.cc registers its options
// and runs one library entry point; this file only dispatches and turns failures into exit codes.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>

#include "app/commands.h"
#include "core/image_io.h"
#include "core/logging.h"
#include "core/provenance.h"

int main(int argc, char** argv) {
  mesocap::SetCommandLine(argc, argv);
  CLI::App app{"mesocap: photographs of a material sample -> a relightable, tileable material"};
  app.set_version_flag("--version", std::string("mesocap ") + mesocap::Version());
  app.require_subcommand(1);
  int verbosity = 1;
  app.add_flag_callback("-q,--quiet", [&] { verbosity = 0; }, "Only warnings and errors");
  app.add_flag_callback("-v,--verbose", [&] { verbosity = 2; }, "Debug output");
  double max_megapixels = double(mesocap::kDefaultMaxImagePixels) / 1e6;
  app.add_option("--max-megapixels", max_megapixels,
                 "Refuse images larger than this before allocating them (a crafted header cannot ask "
                 "for gigabytes)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);

  std::vector<mesocap::app::Command> commands = mesocap::app::AllCommands();
  for (auto& command : commands) command.setup(app);

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
  mesocap::InitLogging(verbosity);
  mesocap::SetMaxImagePixels(int64_t(max_megapixels * 1e6));
  try {
    for (auto& command : commands)
      if (app.got_subcommand(command.name)) return command.run();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "mesocap: internal error: %s\n", e.what());
    return mesocap::app::kExitInternal;
  }
  return mesocap::app::kExitUsage;
}
