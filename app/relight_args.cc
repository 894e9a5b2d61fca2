#include "app/relight_args.h"

#include <CLI/CLI.hpp>

namespace mesocap::app {

CLI::App* AddRelightOptions(CLI::App& app, RelightArgs* args) {
  CLI::App* sub = app.add_subcommand(
      "relight",
      "Relight a .ptm for one light direction. The output holds the PTM's values as stored, "
      "clamped to [0, 1] as RTI viewers show them: an 8-bit file's bytes are round(255 * value) "
      "(no sRGB encoding is added; a PTM fitted from photos is already display-encoded), a 16-bit "
      "file's samples round(65535 * value)");
  sub->add_option("ptm", args->ptm, "PTM_1.2 file (LRGB or RGB)")->required();
  sub->add_option("--light", args->light,
                  "Light direction x,y,z in the surface frame (x right, y up the image, z toward the camera); "
                  "write --light=-0.5,0,1 when x is negative")
      ->required();
  sub->add_option("--out", args->out, "Output image (.png, .tif, .jpg)")->required();
  sub->add_option("--bits", args->bits, "Bits per sample of the output: 8 or 16 (PNG/TIFF)")->capture_default_str();
  sub->add_flag("--linear", args->linear,
                "The PTM holds linear values (fitted with fit-ptm --linearize; a .ptm cannot say so itself): "
                "an 8-bit output is then sRGB-encoded, a 16-bit one stays linear");
  sub->add_option("--threads", args->threads, "Threads (-1: all cores)")->capture_default_str();
  return sub;
}

}  // namespace mesocap::app
