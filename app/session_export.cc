#include "app/session_export.h"

#include <algorithm>
#include <cmath>

#include "app/material_maps.h"
#include "app/session_stages.h"
#include "app/synth_output.h"
#include "core/atomic_file.h"
#include "core/cancel.h"
#include "core/directions.h"
#include "core/image_io.h"
#include "core/session_layout.h"
#include "core/slice_attributes.h"
#include "core/slice_index.h"
#include "core/stage_cache.h"
#include "core/text_format.h"
#include "export/ggx_fit.h"
#include "export/gltf_material.h"
#include "formats/lp_file.h"
#include "export/previews.h"
#include "synth/synth_map.h"

namespace mesocap::app {

namespace fs = std::filesystem;

std::string ExportFormatToString(ExportFormat format) {
  switch (format) {
    case ExportFormat::kPtm: return "ptm";
    case ExportFormat::kLp: return "lp";
    case ExportFormat::kExr: return "exr";
    case ExportFormat::kGltf: return "gltf";
  }
  return "";
}

bool StringToExportFormat(const std::string& name, ExportFormat* format) {
  for (ExportFormat f : AllExportFormats())
    if (ExportFormatToString(f) == name) {
      *format = f;
      return true;
    }
  return false;
}

std::vector<ExportFormat> AllExportFormats() {
  return {ExportFormat::kPtm, ExportFormat::kLp, ExportFormat::kExr, ExportFormat::kGltf};
}

namespace {

std::string MakeItWith(const fs::path& session) { return "run `mesocap process " + session.string() + "`"; }

StatusOr<std::string> ExportPtm(const fs::path& session, const ExportFolder& exports) {
  auto top = TopBoardOfSession(session);
  if (!top.ok()) return Status::Error(top.status().message() + ": " + MakeItWith(session));
  const fs::path ptm = SessionLayout(session).ptm().board_ptm(*top);
  if (!fs::exists(ptm)) return Status::Error(ptm.string() + " not found (the top board's PTM): " + MakeItWith(session));
  const fs::path out = exports.material_ptm();
  MESOCAP_RETURN_IF_ERROR(WriteFileAtomically(out, [&](const fs::path& temp) {
    std::error_code ec;
    fs::copy_file(ptm, temp, fs::copy_options::overwrite_existing, ec);
    return ec ? Status::Error(ptm.string() + ": cannot copy: " + ec.message()) : Status::Ok();
  }));
  return Format("%s (board %d)", out.string().c_str(), *top);
}

StatusOr<std::string> ExportLp(const fs::path& session, const ExportFolder& exports) {
  auto top = TopBoardOfSession(session);
  if (!top.ok()) return Status::Error(top.status().message() + ": " + MakeItWith(session));
  auto index = ReadSliceIndex(SessionLayout(session).slices().index());
  if (!index.ok()) return index.status();
  std::vector<const SliceIndexEntry*> slices;
  for (const SliceIndexEntry& e : index->slices)
    if (e.board == *top) slices.push_back(&e);
  std::vector<Image> images;
  for (const SliceIndexEntry* e : slices) {
    auto image = ReadImage(e->file);
    if (!image.ok()) return image.status();
    images.push_back(std::move(*image));
  }
  // One exposure for all, the brightest slice's 99.5th percentile at white: the images keep
  // their relative intensities as an RTI capture's photos do.
  images = ExposeAll(images, 0.995);
  auto staging = StagingFolder::Begin(exports.lp());
  if (!staging.ok()) return staging.status();
  // The staging folder stands in for lp/ while it is written.
  const auto in_staging = [&](const fs::path& file) { return staging->path() / file.filename(); };
  std::vector<LpEntry> entries;
  for (size_t k = 0; k < images.size(); ++k) {
    const fs::path file = in_staging(exports.lp_slice(int(k) + 1));
    MESOCAP_RETURN_IF_ERROR(WriteImage(file, images[k], {.format = PixelFormat::kUint8Srgb}));
    entries.push_back({file, slices[k]->light});
  }
  MESOCAP_RETURN_IF_ERROR(WriteLpFile(in_staging(exports.lp_file()), entries));
  MESOCAP_RETURN_IF_ERROR(staging->Publish(/*replace=*/true));
  return Format("%s (board %d, %zu images)", exports.lp_file().string().c_str(), *top, entries.size());
}

// The slices of `index` as the parts of one OpenEXR, in index order, each named by its file's
// stem and carrying its directions, read and written one at a time.
Status WriteBtfMultiPart(const SliceIndex& index, const fs::path& path) {
  if (index.slices.empty()) return Status::Error(path.string() + ": the BTF has no slices");
  auto first = ReadImageInfo(index.slices.front().file);
  if (!first.ok()) return first.status();
  std::vector<ExrPartHeader> parts;
  for (const SliceIndexEntry& e : index.slices) {
    ExrPartHeader part;
    part.name = e.file.stem().string();
    part.width = first->width;
    part.height = first->height;
    part.channels = std::min(first->channels, 4);
    part.options.format = PixelFormat::kHalf;
    part.options.channel_names = first->channel_names;
    part.options.channel_names.resize(size_t(part.channels));
    SetSliceAngles(&part.options.attributes, e.theta_i_deg, e.phi_i_deg, e.theta_o_deg, e.phi_o_deg);
    part.options.attributes["mesocap:file"] = e.file.filename().string();
    parts.push_back(std::move(part));
  }
  return WriteMultiPartExr(path, parts, [&](int k) -> StatusOr<Image> {
    if (CancelRequested()) return Status::Cancelled();  // Ctrl-C: a full BTF is thousands of parts
    return ReadImage(index.slices[size_t(k)].file);
  });
}

StatusOr<std::string> ExportExr(const fs::path& session, const ExportFolder& exports, const ExportOptions& options) {
  const BtfFolder btf = SessionLayout(session).btf();
  auto index = ReadSliceIndex(btf.index());
  if (!index.ok()) return Status::Error(index.status().message() + ": " + MakeItWith(session));
  if (options.exr_multipart) MESOCAP_RETURN_IF_ERROR(WriteBtfMultiPart(*index, exports.btf_multipart()));
  auto staging = StagingFolder::Begin(exports.btf().root);
  if (!staging.ok()) return staging.status();
  const BtfFolder staged{staging->path()};
  std::error_code ec;
  fs::create_directories(staged.slices(), ec);
  if (ec) return Status::Error(staging->path().string() + ": cannot create: " + ec.message());
  // Hard links where the file system allows (the slices are never modified in place: a re-run
  // swaps a new folder in), copies elsewhere.
  for (const SliceIndexEntry& e : index->slices) {
    if (CancelRequested()) return Status::Cancelled();
    const fs::path to = staged.root / fs::relative(e.file, btf.root);
    fs::create_hard_link(e.file, to, ec);
    if (ec) {
      ec.clear();
      fs::copy_file(e.file, to, ec);
    }
    if (ec) return Status::Error(e.file.string() + ": cannot copy to " + to.string() + ": " + ec.message());
  }
  fs::copy_file(btf.index(), staged.index(), ec);
  if (ec) return Status::Error(btf.index().string() + ": cannot copy: " + ec.message());
  MESOCAP_RETURN_IF_ERROR(staging->Publish(/*replace=*/true));
  return Format("%s (%zu slices)%s", exports.btf().root.string().c_str(), index->slices.size(),
                options.exr_multipart ? ("; " + exports.btf_multipart().string() + " (one part per slice)").c_str() : "");
}

// SESSION/synth/'s map applied to the fitted material -> OUT/gltf_synth/. It repeats seamlessly
// (sampler REPEAT) when the roller made it of whole tiles (every roller tile has the same
// borders) and when texton synthesis made it (its output wraps around: the seams across its
// edges are as good as inside, synth/photo_texton_test.cc).
StatusOr<std::string> ExportSynthesizedGltf(const fs::path& session, const GgxMaterialMaps& maps, GltfMaterialOptions gltf,
                                            const ExportFolder& exports) {
  const SynthFolder synth = SessionLayout(session).synth();
  auto map = ReadSynthMap(synth.map());
  if (!map.ok()) return map.status();
  if (map->sample_width != maps.base_color.width() || map->sample_height != maps.base_color.height())
    return Status::Error(synth.map().string() + ": points into a sample of another size than the BTF; "
                         "run `mesocap process " + session.string() + " --force synth`");
  bool tileable = map->method == "texton";
  std::string not_tileable = "not tileable";
  if (map->method == "roller") {
    // Whole tiles only when the report says which tile (a roller map applied by synth-apply
    // records none); an unreadable report is said, not taken for a tile.
    if (auto report = ReadSynthReportSummary(synth); !report.ok()) {
      not_tileable = "not tileable: " + report.status().message();
    } else {
      const int tw = report->tile_width, th = report->tile_height;
      tileable = tw > 0 && th > 0 && map->width % tw == 0 && map->height % th == 0;
    }
  }
  auto staging = StagingFolder::Begin(exports.gltf_synth().root);
  if (!staging.ok()) return staging.status();
  gltf.name += " (" + map->method + ")";
  gltf.patch_m *= double(map->width) / maps.base_color.width();
  gltf.tileable = tileable;
  MESOCAP_RETURN_IF_ERROR(WriteGltfMaterial({staging->path()}, ApplyMapToMaterial(*map, maps), gltf));
  MESOCAP_RETURN_IF_ERROR(staging->Publish(/*replace=*/true));
  return Format("; %s (%s %dx%d, %s)", exports.gltf_synth().material().string().c_str(), map->method.c_str(),
                map->width, map->height, !tileable                 ? not_tileable.c_str()
                : map->method == "texton" ? "tileable: it wraps around"
                                          : "tileable: whole roller tiles");
}

StatusOr<std::string> ExportGltf(const fs::path& session, const ExportFolder& exports, const GgxMaterialMaps* fitted) {
  const fs::path index = SessionLayout(session).btf().index();
  if (!fs::exists(index))
    return Status::Error(index.string() + " not found (a glTF material is fitted to the reconstructed BTF): " + MakeItWith(session));
  auto layout = LoadSessionLayout(session, "");
  const double patch_m = layout.ok() && !layout->boards.empty() ? layout->boards.front().patch_m : 0.064;
  GgxFitOptions options;
  auto maps = fitted ? StatusOr<GgxMaterialMaps>(*fitted) : FitGgxMaterial(index, options);
  if (!maps.ok()) return maps.status();
  auto staging = StagingFolder::Begin(exports.gltf().root);
  if (!staging.ok()) return staging.status();
  const GltfFolder staged{staging->path()};
  GltfMaterialOptions gltf;
  gltf.name = fs::absolute(session).lexically_normal().filename().string();
  gltf.patch_m = patch_m;
  MESOCAP_RETURN_IF_ERROR(WriteGltfMaterial(staged, *maps, gltf));
  // Black 0, white 50% or more, at least 256 pixels wide so a small material stays legible.
  MESOCAP_RETURN_IF_ERROR(WriteImage(staged.fit_error(".png"), GreyPicture(maps->relative_error, 2, 256),
                                     {.format = PixelFormat::kUint8Srgb}));
  MESOCAP_RETURN_IF_ERROR(WriteImage(staged.fit_error(".exr"), maps->relative_error, {.format = PixelFormat::kHalf}));
  Json report = maps->ToJson();
  report["options"] = options.ToJson();
  report["model"] = "glTF 2.0 metallic-roughness (GGX, separable Smith, Schlick), fitted per texel with Ceres";
  report["fit_error"] = staged.fit_error(".exr").filename().string() + ": per texel, RMS residual / RMS value over the slices used; " +
                       staged.fit_error(".png").filename().string() + ": x2, white >= 50%";
  MESOCAP_RETURN_IF_ERROR(WriteJsonFile(staged.fit_report(), report));
  MESOCAP_RETURN_IF_ERROR(staging->Publish(/*replace=*/true));
  std::string synthesized;
  // The synthesized material only when the stage cache says synth/ was made from the BTF as it is
  // now; one made from an earlier reconstruction is left out, and an export of it removed.
  auto cache = StageCache::Open(session);
  if (!cache.ok()) return cache.status();
  if (cache->MadeFromCurrent("synth", "reconstruct")) {
    auto written = ExportSynthesizedGltf(session, *maps, gltf, exports);
    if (!written.ok()) return written.status();
    synthesized = *written;
  } else if (std::error_code ec; fs::exists(exports.gltf_synth().root, ec)) {
    fs::remove_all(exports.gltf_synth().root, ec);
    synthesized = "; " + exports.gltf_synth().root.string() + " removed: " +
                  SessionLayout(session).Relative(SessionLayout(session).synth().root) +
                  "/ was not made from this BTF (mesocap process --synth)";
  }
  return Format("%s (%dx%d texels from %d slices, median relative error %.1f%%, %.1f s)%s",
                exports.gltf().material().string().c_str(), maps->base_color.width(),
                maps->base_color.height(), maps->slices_used, 100 * maps->median_relative_error, maps->seconds,
                synthesized.c_str());
}

}  // namespace

StatusOr<std::string> ExportSession(const fs::path& session, ExportFormat format, const fs::path& out_dir,
                                    const ExportOptions& options) {
  std::error_code ec;
  fs::create_directories(out_dir, ec);
  if (ec) return Status::Error(out_dir.string() + ": cannot create: " + ec.message());
  switch (format) {
    case ExportFormat::kPtm: return ExportPtm(session, {out_dir});
    case ExportFormat::kLp: return ExportLp(session, {out_dir});
    case ExportFormat::kExr: return ExportExr(session, {out_dir}, options);
    case ExportFormat::kGltf: return ExportGltf(session, {out_dir}, options.fitted);
  }
  return Status::Error("unknown export format");
}

}  // namespace mesocap::app
