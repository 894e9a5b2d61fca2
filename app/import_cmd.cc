// mesocap import: build a session from folders of photos taken elsewhere.
#include <cstdio>
#include <memory>

#include "app/commands.h"
#include "capture/import.h"
#include "core/progress.h"

namespace mesocap::app {
namespace {

struct ImportArgs {
  ImportOptions options;
  std::string link = "hardlink";
  bool no_progress = false;
};

}  // namespace

Command ImportCommand() {
  auto args = std::make_shared<ImportArgs>();
  Command c;
  c.name = "import";
  c.setup = [args](CLI::App& app) {
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
  };
  c.run = [args]() {
    if (!StringToLinkMode(args->link, &args->options.link_mode))
      return Fail("import", "--link must be hardlink or copy, not '" + args->link + "'", kExitUsage);
    if (std::string why = args->options.Check(); !why.empty()) return Fail("import", why, kExitUsage);
    ProgressBar bar("import", !args->no_progress);
    auto report = ImportPhotoFolder(args->options, bar.AsCallback());
    if (!report.ok()) {
      const bool cancelled = report.status().message() == "cancelled";
      return Fail("import", report.status().message(), cancelled ? kExitCancelled : kExitFailure);
    }
    std::printf("%s\n", report->Brief().c_str());  // skipped files are listed, exit code stays 0
    return kExitOk;
  };
  return c;
}

}  // namespace mesocap::app
