// mesocap export SESSION --format ptm|lp|exr: a processed session's results in the forms other
// tools open (app/session_export.h), into --out (default SESSION/export).
#include "app/export_args.h"

#include <cstdio>
#include <memory>

#include "app/commands.h"
#include "app/session_export.h"
#include "core/session.h"

namespace mesocap::app {
namespace {

namespace fs = std::filesystem;

}  // namespace

int RunExport(const ExportArgs& a) {
  std::vector<ExportFormat> formats;
  for (const std::string& name : a.formats) {
    ExportFormat f;
    if (!StringToExportFormat(name, &f)) return Fail("export", "--format must be ptm, lp, exr or gltf, not '" + name + "'", kExitUsage);
    formats.push_back(f);
  }
  if (auto session = Session::Open(a.session); !session.ok()) return Fail("export", session.status().message());
  const fs::path out = a.out.empty() ? a.session / "export" : a.out;
  for (ExportFormat f : formats) {
    auto written = ExportSession(a.session, f, out, a.options);
    if (!written.ok()) return Fail("export", written.status().message());
    std::printf("export %s: %s\n", ExportFormatToString(f).c_str(), written->c_str());
  }
  return kExitOk;
}
}  // namespace mesocap::app
