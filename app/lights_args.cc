#include "app/lights_args.h"

#include <CLI/CLI.hpp>

namespace mesocap::app {

CLI::App* AddLightsOptions(CLI::App& app, LightsArgs* args) {
  CLI::App* sub = app.add_subcommand(
      "lights",
      "Light directions from a reflective sphere in a folder of RTI photos (camera and sphere fixed, the light "
      "moves): the mirror highlight on the sphere in each photo gives its light. Writes a .lp file and a JSON "
      "report of every photo (skipped ones with the reason)");
  sub->add_option("--images", args->images, "Folder of photos (.jpg, .png, .tif, .exr)")->required();
  sub->add_option("--sphere-mask", args->sphere_mask, "Image of the sphere's mask, white = sphere, same size as the photos");
  sub->add_option("--sphere", args->sphere, "The sphere's circle instead of a mask: x,y,r in pixels (write --sphere=x,y,r)");
  sub->add_option("--out", args->out, "Light file (.lp); default IMAGES/lights.lp. The report goes beside it (.json)");
  sub->add_option("--saturation", args->options.saturation, "Linear value from which a pixel counts as clipped")
      ->capture_default_str();
  sub->add_option("--max-highlight-radius", args->options.max_blob_radius,
                  "Largest highlight, as a fraction of the sphere's radius")
      ->capture_default_str();
  return sub;
}

}  // namespace mesocap::app
