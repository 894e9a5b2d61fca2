// `mesocap export` and the export stage of `mesocap process`: a session's results in the forms
// other tools open. Each format writes one item into the output folder, whole or not at all:
//   ptm: material.ptm, the top board's PTM (RTIViewer, relight);
//   lp:  lp/material.lp with the top board's slices as 8-bit PNGs under one exposure (an RTI
//        capture for RTIBuilder, relight-cli or `mesocap fit-ptm`);
//   exr: btf/, the reconstructed BTF as OpenEXR slices with index.json (format mesocap-btf), and
//        with exr_multipart also btf.exr, the same slices as the parts of one multi-part OpenEXR;
//   gltf: gltf/, a glTF 2.0 metallic-roughness material fitted per texel to the reconstructed BTF
//        (export/ggx_fit.h) on a preview quad and sphere, with its fit error map and fit.json.
// A missing input is named with the command that makes it.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "core/status.h"

namespace mesocap {
struct GgxMaterialMaps;
}

namespace mesocap::app {

enum class ExportFormat { kPtm, kLp, kExr, kGltf };
std::string ExportFormatToString(ExportFormat format);
bool StringToExportFormat(const std::string& name, ExportFormat* format);
std::vector<ExportFormat> AllExportFormats();

struct ExportOptions {
  bool exr_multipart = false;  // exr: also btf.exr
  // gltf: the GGX fit already made (the merge of a sharded fit); null: fitted here.
  const GgxMaterialMaps* fitted = nullptr;
};

// Writes `format` from `session` into `out_dir` (created if missing); returns what it wrote.
StatusOr<std::string> ExportSession(const std::filesystem::path& session, ExportFormat format,
                                    const std::filesystem::path& out_dir, const ExportOptions& options = {});

}  // namespace mesocap::app
