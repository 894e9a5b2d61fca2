#include "app/fit_ptm_args.h"

#include <CLI/CLI.hpp>

namespace mesocap::app {

CLI::App* AddFitPtmOptions(CLI::App& app, FitPtmArgs* args) {
  CLI::App* sub = app.add_subcommand(
      "fit-ptm", "Fit a polynomial texture map to an RTI capture (.lp light file + photos); writes .ptm and .json");
  sub->add_option("--lp", args->lp, "RTI light-position file (first line: count; then 'image x y z')")
      ->required();
  sub->add_option("--out", args->out, "Output .ptm (PTM_1.2); the report goes beside it as .json")->required();
  sub->add_option("--format", args->format, "lrgb: luminance polynomial times colour; rgb: one polynomial per channel")
      ->capture_default_str();
  sub->add_option("--normals", args->normals, "Also write surface normals (n+1)/2 to this image (16-bit PNG/TIFF)");
  sub->add_option("--albedo", args->albedo, "Also write the albedo estimate to this image (16-bit PNG/TIFF)");
  sub->add_flag("--linearize", args->linearize,
                "Decode 8-bit photos from sRGB to linear before fitting (default: fit the stored values, as RTI "
                "tools and viewers expect)");
  sub->add_option("--threads", args->threads, "Threads (-1: all cores)")->capture_default_str();
  sub->add_flag("--no-progress", args->no_progress, "Do not draw a progress bar");
  return sub;
}

}  // namespace mesocap::app
