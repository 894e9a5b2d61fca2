// mesocap import: build a session from folders of photos taken elsewhere.
#include "app/import_args.h"

#include <cstdio>
#include <memory>

#include "app/commands.h"
#include "capture/import.h"
#include "core/progress.h"

namespace mesocap::app {
namespace {

}  // namespace

int RunImport(ImportArgs& a) {
  if (!StringToLinkMode(a.link, &a.options.link_mode))
    return Fail("import", "--link must be hardlink or copy, not '" + a.link + "'", kExitUsage);
  if (std::string why = a.options.Check(); !why.empty()) return Fail("import", why, kExitUsage);
  ProgressBar bar("import", !a.no_progress);
  auto report = ImportPhotoFolder(a.options, bar.AsCallback());
  if (!report.ok()) return Fail("import", report.status());
  std::printf("%s\n", report->Brief().c_str());  // skipped files are listed, exit code stays 0
  return kExitOk;
}
}  // namespace mesocap::app
