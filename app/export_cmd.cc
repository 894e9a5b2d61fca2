// mesocap export SESSION --format ptm|lp|exr: a processed session's results in the forms other
// tools open (app/session_export.h), into --out (default SESSION/export).
#include "app/export_args.h"

#include <cstdio>
#include <memory>
#include <optional>

#include "app/commands.h"
#include "app/session_export.h"
#include "core/session.h"
#include "core/session_layout.h"
#include "core/session_lock.h"

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
  if (auto session = Session::Open(a.session); !session.ok()) return Fail("export", session.status());
  const fs::path out = a.out.empty() ? SessionLayout(a.session).exports().root : a.out;
  // Into the session, export is one of its writers; elsewhere it only reads the session.
  const std::string inside = fs::absolute(out).lexically_normal().lexically_relative(fs::absolute(a.session).lexically_normal()).string();
  std::optional<SessionLock> lock;
  if (!inside.empty() && inside.rfind("..", 0) != 0) {
    auto taken = SessionLock::Acquire(a.session, "export");
    if (!taken.ok()) return Fail("export", taken.status());
    lock.emplace(std::move(*taken));
  }
  for (ExportFormat f : formats) {
    auto written = ExportSession(a.session, f, out, a.options);
    if (!written.ok()) return Fail("export", written.status());
    std::printf("export %s: %s\n", ExportFormatToString(f).c_str(), written->c_str());
  }
  return kExitOk;
}
}  // namespace mesocap::app
