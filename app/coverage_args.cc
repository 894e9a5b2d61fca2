#include "app/coverage_args.h"

#include <CLI/CLI.hpp>

#include "core/session_layout.h"

namespace mesocap::app {

CLI::App* AddCoverageOptions(CLI::App& app, CoverageArgs* args) {
  const SessionLayout S = HelpLayout();
  CLI::App* sub = app.add_subcommand(
      "coverage",
      "Capture guidance: per board, the light directions measured so far, a score against what the BTF "
      "reconstruction needs, and the next flash positions that would add most (" + S.coverage().root.string() + "/)");
  sub->add_option("session", args->session, "Calibrated session folder (reads " + S.Relative(S.calibration().rig()) + ", and " +
                      S.Relative(S.slices().index()) + " when present)")
      ->required();
  sub->add_option("--out", args->out, "Output folder (default " + S.coverage().root.string() + "; replaced on a re-run)");
  sub->add_option("--layout", args->layout_file,
                  "Rig layout (default " + S.rig_layout().string() + "): predicts which flash positions shadow which board");
  sub->add_option("--near-deg", args->options.near_deg, "A target light within this of a measured one is covered")
      ->capture_default_str();
  sub->add_option("--suggest", args->options.suggestions, "How many next flash positions to list")->capture_default_str();
  sub->add_option("--objective", args->objective,
                  "How the next positions are chosen: spread (where the measured lights are sparsest) or near (most "
                  "targets brought within --near-deg)")
      ->check(CLI::IsMember({"spread", "near"}))
      ->capture_default_str();
  sub->add_flag("--no-mirror-symmetry", args->no_mirror_symmetry,
                "Count each board's own lights only, instead of also the images of other boards' lights under the "
                "material's symmetries that its slices show hold (as the reconstruction borrows them)");
  return sub;
}

}  // namespace mesocap::app
