// mesocap export SESSION --format ptm|lp|exr: a processed session's results in the forms other
// tools open (app/session_export.h), into --out (default SESSION/export).
#include <cstdio>
#include <memory>

#include "app/commands.h"
#include "app/session_export.h"
#include "core/session.h"

namespace mesocap::app {
namespace {

namespace fs = std::filesystem;

struct ExportArgs {
  fs::path session, out;
  std::vector<std::string> formats;
  ExportOptions options;
};

int Run(const ExportArgs& a) {
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

}  // namespace

Command ExportCommand() {
  auto args = std::make_shared<ExportArgs>();
  Command c;
  c.name = "export";
  c.setup = [args](CLI::App& app) {
    CLI::App* sub = app.add_subcommand("export", "Write a processed session's material as .ptm, .lp + images, an OpenEXR BTF or a glTF PBR material");
    sub->add_option("session", args->session, "Session folder (after `mesocap process`)")->required();
    sub->add_option("--format", args->formats, "ptm (top board's PTM), lp (RTI light file + PNGs), exr (BTF folder), gltf (PBR material fitted to the BTF); repeatable")
        ->required();
    sub->add_flag("--multipart", args->options.exr_multipart,
                  "exr: also btf.exr, every slice as a part of one multi-part OpenEXR (named by the slice, with its directions)");
    sub->add_option("--out", args->out, "Output folder (default SESSION/export); each format's item is replaced whole");
  };
  c.run = [args]() { return Run(*args); };
  return c;
}

}  // namespace mesocap::app
