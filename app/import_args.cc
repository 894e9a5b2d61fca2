#include "app/import_args.h"

#include <CLI/CLI.hpp>

namespace mesocap::app {

CLI::App* AddImportOptions(CLI::App& app, ImportArgs* args) {
  CLI::App* sub = app.add_subcommand(
      "import", "Make a session from a folder of photos (JPEG, PNG, TIFF, camera RAW), ordered by capture time");
  ImportOptions& o = args->options;
  sub->add_option("photo_dir", o.photo_dir, "Folder of flash shots (not searched recursively)")->required();
  sub->add_option("--out", o.out, "New session folder (must not exist or be empty)")->required();
  sub->add_option("--calibration-dir", o.calibration_dir, "Folder of checkerboard calibration shots");
  sub->add_option("--link", args->link,
                  "hardlink: hard-link originals, copying when that is impossible; copy: always copy")
      ->capture_default_str();
  sub->add_flag("--no-progress", args->no_progress, "Do not draw a progress bar");
  return sub;
}

}  // namespace mesocap::app
