#include "app/commands.h"

#include <cstdio>

#include "core/provenance.h"

namespace mesocap::app {

int Fail(const std::string& verb, const std::string& message, int code) {
  std::fprintf(stderr, "mesocap %s: %s\n", verb.c_str(), message.c_str());
  return code;
}

std::vector<Command> AllCommands() { return {SimulateCommand(), DemoCommand(),     ImportCommand(),          CaptureCommand(),
          CamerasCommand(),  CalibrateCommand(), CalibrateCameraCommand(), FitPtmCommand(), RelightCommand(),
          ReconstructCommand(), EvaluateCommand(), LightsCommand(), SynthCommand(), SynthApplyCommand(), PaintCommand(), ProcessCommand(), ExportCommand(), CoverageCommand()}; }

void DefineCommandLine(CLI::App& app, GlobalOptions& globals, std::vector<Command>& commands) {
  app.name("mesocap");
  app.description("mesocap: photographs of a material sample -> a relightable, tileable material");
  app.set_version_flag("--version", std::string("mesocap ") + Version());
  app.require_subcommand(1);
  app.add_flag_callback("-q,--quiet", [&globals] { globals.verbosity = 0; }, "Only warnings and errors");
  app.add_flag_callback("-v,--verbose", [&globals] { globals.verbosity = 2; }, "Debug output");
  app.add_option("--max-megapixels", globals.max_megapixels,
                 "Refuse images larger than this before allocating them (a crafted header cannot ask "
                 "for gigabytes)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  commands = AllCommands();
  for (auto& command : commands) command.setup(app);
}

}  // namespace mesocap::app
