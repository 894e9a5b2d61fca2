#include "app/export_args.h"

#include <CLI/CLI.hpp>

#include "core/session_layout.h"

namespace mesocap::app {

CLI::App* AddExportOptions(CLI::App& app, ExportArgs* args) {
  const SessionLayout S = HelpLayout();
  CLI::App* sub = app.add_subcommand("export", "Write a processed session's material as .ptm, .lp + images, an OpenEXR BTF or a glTF PBR material");
  sub->add_option("session", args->session, "Session folder (after `mesocap process`)")->required();
  sub->add_option("--format", args->formats, "ptm (top board's PTM), lp (RTI light file + PNGs), exr (BTF folder), gltf (PBR material fitted to the BTF); repeatable")
      ->required();
  sub->add_flag("--multipart", args->options.exr_multipart,
                "exr: also " + S.exports().btf_multipart().filename().string() + ", every slice as a part of one multi-part OpenEXR (named by the slice, with its directions)");
  sub->add_option("--out", args->out, "Output folder (default " + S.exports().root.string() + "); each format's item is replaced whole");
  return sub;
}

}  // namespace mesocap::app
