// mesocap: one subcommand per stage. This front only parses the command line (app/commands.h):
// the chosen command runs in the commands module, loaded here, so that asking for help or the
// version maps none of the libraries the commands need (issue 14).
#include <CLI/CLI.hpp>

#include <cstdio>
#include <vector>

#include "app/command_line.h"
#include "app/commands.h"
#include "core/module_loader.h"

namespace {

// Only the module beside the executable (installed together, or both in build/app/): a front never
// runs a module of another build, whose options structs could differ from its own.
int RunInModule(const mesocap::app::CommandOptions& command, const mesocap::app::GlobalOptions& globals, int argc,
                char** argv) {
  using namespace mesocap::app;
  auto run = mesocap::LoadModuleSymbol(kCommandsModuleName, "", kRunCommandSymbol);
  if (!run.ok()) {
    std::fprintf(stderr, "mesocap: %s\n", run.status().message().c_str());
    return kExitInternal;
  }
  return reinterpret_cast<RunCommandFn>(*run)(command.verb, command.args.get(), command.args_size, &globals, argc, argv);
}

}  // namespace

int main(int argc, char** argv) {
  // Results are printed line by line as stages finish; piped into a log or `tee`, stdout would
  // otherwise hold them all until exit.
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  CLI::App app;
  mesocap::app::GlobalOptions globals;
  std::vector<mesocap::app::CommandOptions> commands;
  mesocap::app::DefineCommandLine(app, &globals, &commands);

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
  for (const auto& command : commands)
    if (command.subcommand->parsed()) return RunInModule(command, globals, argc, argv);
  return mesocap::app::kExitUsage;
}
