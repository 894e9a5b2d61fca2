#include "app/evaluate_args.h"

#include <CLI/CLI.hpp>

#include "core/session_layout.h"

namespace mesocap::app {

CLI::App* AddEvaluateOptions(CLI::App& app, EvaluateArgs* args) {
  const SessionLayout S = HelpLayout();
  CLI::App* sub = app.add_subcommand(
      "evaluate", "Score the statistical BTF reconstruction against a virtual material's true BTF (paper's validation)");
  CLI::Option* material = sub->add_option("--material", args->material, "Virtual material")->capture_default_str();
  sub->add_option("--session", args->session,
                  "A virtual session (mesocap simulate, then calibrate): reconstruct from its calibrated slices "
                  "(" + S.slices().root.string() + ") and score against its material's true BTF")
      ->excludes(material);
  sub->add_option("--out", args->out, "Output folder (must not exist or be empty)")->required();
  sub->add_option("--size", args->size, "Texels per side of every slice (power of two)")->capture_default_str();
  sub->add_option("--pairs", args->pairs, "Score this many held-out pairs, evenly spread (-1: all)")->capture_default_str();
  sub->add_option("--samples-per-axis", args->samples_per_axis,
                  "True slices: samples per texel axis (area average); 0: 2 with --material (inputs and targets "
                  "alike), with --session as many as the rig rendered the material's patch with (512 / --size, at "
                  "least 2), the finest detail its shots hold")
      ->capture_default_str()
      ->check(CLI::Range(0, 64));
  sub->add_flag("--pixel-only", args->pixel_only, "Match the pixel histogram only (no subbands), for comparison");
  sub->add_option("--max-view-extrapolation", args->max_view_extrapolation,
                  "Extrapolate view statistics at most this many ring spacings beyond the outer ring")
      ->capture_default_str();
  args->method.AddTo(sub);
  sub->add_option("--threads", args->threads, "Threads (-1: all cores)")->capture_default_str();
  sub->add_flag("--no-progress", args->no_progress, "Do not draw a progress bar");
  return sub;
}

}  // namespace mesocap::app
