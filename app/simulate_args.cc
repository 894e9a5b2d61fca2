#include "app/simulate_args.h"

#include <CLI/CLI.hpp>

namespace mesocap::app {

CLI::App* AddSimulateOptions(CLI::App& app, SimulateArgs* args) {
  CLI::App* sub = app.add_subcommand("simulate", "Render a virtual capture session with known ground truth");
  SimulateOptions& o = args->session;
  sub->add_option("--out", o.out, "Output session folder (must not exist or be empty); with --true-btf an .exr file")->required();
  std::string names;
  for (const auto& m : MaterialCatalog()) names += (names.empty() ? "" : ", ") + m.name;
  sub->add_option("--material", o.rig.material, "Material: " + names)->capture_default_str();
  sub->add_option("--shots", o.rig.shots, "Flash shots")->capture_default_str();
  sub->add_option("--calib-shots", o.rig.calib_shots, "Checkerboard shots")->capture_default_str();
  sub->add_option("--seed", o.rig.seed, "Random seed: same seed, same bytes")->capture_default_str();
  sub->add_option("--width", o.rig.width, "Image width in pixels")->capture_default_str();
  sub->add_option("--height", o.rig.height, "Image height in pixels")->capture_default_str();
  sub->add_option("--format", o.image_format, "Shot files: jpg (8-bit sRGB), png (16-bit linear), exr (float linear)")
      ->capture_default_str();
  sub->add_option("--samples-per-axis", o.render.samples_per_axis, "Anti-aliasing samples per pixel axis")
      ->capture_default_str();
  sub->add_option("--threads", o.render.num_threads, "Threads (-1: all cores)")->capture_default_str();
  sub->add_flag("--no-progress", args->no_progress, "Do not draw a progress bar");
  sub->add_flag("--true-btf", args->true_btf, "Render one true BTF slice of --material to --out (.exr)");
  sub->add_option("--theta-i", args->btf.theta_i_deg, "True BTF: light zenith angle, degrees");
  sub->add_option("--phi-i", args->btf.phi_i_deg, "True BTF: light azimuth, degrees");
  sub->add_option("--theta-o", args->btf.theta_o_deg, "True BTF: view zenith angle, degrees");
  sub->add_option("--phi-o", args->btf.phi_o_deg, "True BTF: view azimuth, degrees");
  sub->add_option("--size", args->btf.size, "True BTF: texels per side")->capture_default_str();
  return sub;
}

}  // namespace mesocap::app
