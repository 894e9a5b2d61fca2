#include "app/demo_args.h"

#include <CLI/CLI.hpp>

namespace mesocap::app {

CLI::App* AddDemoOptions(CLI::App& app, DemoArgs* args) {
  CLI::App* sub = app.add_subcommand("demo", "Run the virtual rig through every working stage; results and a report in one folder");
  sub->add_option("--out", args->out, "Output folder (must not exist or be empty)")->capture_default_str();
  sub->add_option("--material", args->simulate.rig.material, "Material of the virtual sample")->capture_default_str();
  sub->add_option("--shots", args->simulate.rig.shots, "Flash shots")->capture_default_str();
  sub->add_option("--seed", args->simulate.rig.seed, "Random seed")->capture_default_str();
  sub->add_option("--width", args->simulate.rig.width, "Image width")->capture_default_str();
  sub->add_option("--height", args->simulate.rig.height, "Image height")->capture_default_str();
  sub->add_flag("--no-progress", args->no_progress, "Do not draw progress bars");
  return sub;
}

}  // namespace mesocap::app
