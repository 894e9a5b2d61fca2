#include "app/layout_args.h"

#include <CLI/CLI.hpp>

namespace mesocap::app {

CLI::App* AddLayoutOptions(CLI::App& app, LayoutArgs* args) {
  CLI::App* sub = app.add_subcommand(
      "layout", "Where every file and folder of a session lives, for scripts and pages that read or write one");
  sub->add_option("session", args->session, "Session folder (need not exist yet)")->required();
  sub->add_flag("--json", args->json,
                "Print JSON: the session's absolute root and every path relative to it, grouped by stage");
  return sub;
}

}  // namespace mesocap::app
