#include "app/reconstruct_args.h"

#include <CLI/CLI.hpp>

#include "core/session_layout.h"

namespace mesocap::app {

CLI::App* AddReconstructOptions(CLI::App& app, ReconstructArgs* args) {
  const SessionLayout S = HelpLayout();
  CLI::App* sub = app.add_subcommand("reconstruct", "Reconstruct a full BTF from a session's measured slices (statistical, Ngan & Durand)");
  sub->add_option("session", args->session, "Session folder (reads " + S.slices().index().string() + ")");
  sub->add_option("--slices", args->index, "A slice " + S.slices().index().filename().string() + " instead of the session's");
  sub->add_option("--out", args->out, "Output folder (must not exist or be empty)")->required();
  sub->add_option("--pair", args->pairs, "theta_i,phi_i,theta_o,phi_o in degrees (repeatable; default: the Bonn 81x81 grid)");
  sub->add_option("--grid", args->grid, "Without --pair: every light with every view of 'bonn' (81 directions, "
                  "6561 slices) or 'coarse' (17 directions, 289 slices)")->capture_default_str();
  sub->add_option("--size", args->options.size, "Resample slices to this many texels a side (power of two; 0 keeps theirs)")
      ->capture_default_str();
  sub->add_flag("--pixel-only", args->pixel_only, "Match the pixel histogram only (no subbands)");
  args->method.AddTo(sub);
  sub->add_option("--threads", args->options.btf.num_threads, "Threads (-1: all cores)")->capture_default_str();
  sub->add_flag("--no-progress", args->no_progress, "Do not draw a progress bar");
  return sub;
}

}  // namespace mesocap::app
