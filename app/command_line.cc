#include "app/command_line.h"

#include <string>

#include "app/command_args.h"
#include "core/provenance.h"

namespace mesocap::app {
namespace {

template <typename Args>
CommandOptions OptionsOf(const char* verb, CLI::App* (*add_options)(CLI::App&, Args*), CLI::App& app) {
  auto args = std::make_shared<Args>();
  CLI::App* subcommand = add_options(app, args.get());
  return {verb, subcommand, args, sizeof(Args)};
}

}  // namespace

void DefineCommandLine(CLI::App& app, GlobalOptions* globals, std::vector<CommandOptions>* commands) {
  app.name("mesocap");
  app.description("mesocap: photographs of a material sample -> a relightable, tileable material");
  app.set_version_flag("--version", std::string("mesocap ") + Version());
  app.require_subcommand(1);
  app.add_flag_callback("-q,--quiet", [globals] { globals->verbosity = 0; }, "Only warnings and errors");
  app.add_flag_callback("-v,--verbose", [globals] { globals->verbosity = 2; }, "Debug output");
  app.add_option("--max-megapixels", globals->max_megapixels,
                 "Refuse images larger than this before allocating them (a crafted header cannot ask "
                 "for gigabytes)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
#define MESOCAP_ADD_OPTIONS(Verb) commands->push_back(OptionsOf(#Verb, &Add##Verb##Options, app));
  MESOCAP_FOR_EACH_COMMAND(MESOCAP_ADD_OPTIONS)
#undef MESOCAP_ADD_OPTIONS
}

}  // namespace mesocap::app
