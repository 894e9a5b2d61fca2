// SESSION/report.html of `mesocap process` (app/process.h): the stage table, calibration
// tables and plots, every warning and rejected item, the results' pictures and the WebGL viewer.
#include "app/process.h"

#include <algorithm>
#include <cctype>
#include <map>
#include <set>

#include "core/atomic_file.h"
#include "core/image_io.h"
#include "core/json.h"
#include "core/slice_index.h"
#include "core/text_format.h"
#include "export/previews.h"
#include "export/report.h"

namespace mesocap::app {

namespace fs = std::filesystem;

namespace {

// The viewer the export stage built (export/previews/viewer.html), placed in the page.
Status AddViewer(const fs::path& session, Report* report) {
  const fs::path fragment = session / "export" / "previews" / "viewer.html";
  if (!fs::exists(fragment)) return Status::Ok();
  auto html = ReadTextFile(fragment);
  if (!html.ok()) return html.status();
  report->Heading("Relight it");
  report->Html(*html, "report.html relights the top board's PTM and the reconstructed BTF here, in WebGL.");
  return Status::Ok();
}

// Which light directions each board measured (its own frame): where the reconstruction has
// data and where it extrapolates. The picture goes in SESSION/report_files/, beside the report
// and outside every stage's outputs.
Status AddLightCoverage(const fs::path& session, Report* report) {
  auto index = ReadSliceIndex(session / "slices" / "index.json");
  if (!index.ok()) return Status::Ok();  // no slices: the stage table says why
  std::map<int, std::vector<Eigen::Vector3d>> lights;
  for (const SliceIndexEntry& e : index->slices) lights[e.board].push_back(e.light);
  std::vector<Image> plots;
  std::vector<std::string> labels;
  for (const auto& [board, dirs] : lights) {
    plots.push_back(HemispherePlot(dirs, 240, Format("board %d", board)));
    labels.push_back(Format("board %d: %zu lights", board, dirs.size()));
  }
  if (plots.empty()) return Status::Ok();
  std::error_code ec;
  fs::create_directories(session / "report_files", ec);
  if (ec) return Status::Error((session / "report_files").string() + ": cannot create: " + ec.message());
  MESOCAP_RETURN_IF_ERROR(WriteImage(session / "report_files" / "light_coverage.png", ContactSheet(plots, labels, 5, 200),
                                     {.format = PixelFormat::kUint8Srgb}));
  report->Heading("Light coverage");
  report->Paragraph("The flash directions each board measured, in its own frame (centre: its normal; rings at 30, 60 and "
                    "90 deg). The reconstruction interpolates between them and extrapolates beyond: a tilted board "
                    "never sees the flash from below its slope.");
  report->Picture("report_files/light_coverage.png", "Measured light directions per board");
  return Status::Ok();
}

// The camera and every board's pose with its uncertainty, from calibration/rig.json.
void AddCalibrationTables(const fs::path& session, Report* report) {
  auto rig = ReadJsonFile(session / "calibration" / "rig.json");
  if (!rig.ok()) return;
  const Json camera = rig->value("camera", Json::object());
  if (camera.contains("K")) {
    const Json& K = camera["K"];
    report->Table({"width", "height", "fx px", "fy px", "cx px", "cy px"},
                  {{std::to_string(camera.value("width", 0)), std::to_string(camera.value("height", 0)),
                    Format("%.1f", K[0][0].get<double>()), Format("%.1f", K[1][1].get<double>()),
                    Format("%.1f", K[0][2].get<double>()), Format("%.1f", K[1][2].get<double>())}});
  }
  std::vector<std::vector<std::string>> rows;
  for (const Json& b : rig->value("boards", Json::array())) {
    if (!b.value("found", false)) {
      rows.push_back({std::to_string(b.value("id", -1)), "not posed: " + b.value("why_not", std::string()), "", "", "", ""});
      continue;
    }
    rows.push_back({std::to_string(b.value("id", -1)), std::to_string(b.value("shots_seen", 0)),
                    std::to_string(b.value("corners_used", 0)), Format("%.3f", b.value("rms_reprojection_px", 0.0)),
                    Format("%.4f", b.value("rotation_stddev_deg", 0.0)), Format("%.3f", b.value("translation_stddev_mm", 0.0))});
  }
  report->Table({"board", "shots seen", "tag corners", "RMS reprojection px", "rotation sd deg", "translation sd mm"}, rows);
}

// A reason with its figures replaced by "N" ("12.5% of the patch saturated" -> "N% of the patch
// saturated"): rows that differ only in their numbers group together.
std::string ReasonKind(const std::string& reason) {
  std::string kind;
  for (size_t i = 0; i < reason.size();) {
    if (std::isdigit(static_cast<unsigned char>(reason[i]))) {
      while (i < reason.size() && (std::isdigit(static_cast<unsigned char>(reason[i])) || reason[i] == '.')) ++i;
      kind += "N";
    } else {
      kind += reason[i++];
    }
  }
  return kind;
}

// Every rejected calibration item and every skipped (board, shot): grouped by reason with counts,
// the full list folded away under them.
void AddRejectedItems(const fs::path& session, Report* report) {
  std::vector<std::vector<std::string>> rows;
  if (auto calibration = ReadJsonFile(session / "calibration" / "report.json"); calibration.ok())
    for (const Json& r : calibration->value("rejected", Json::array()))
      if (r.is_string()) rows.push_back({"calibration", "", r.get<std::string>()});
  if (auto slices = ReadJsonFile(session / "slices" / "index.json"); slices.ok())
    for (const Json& s : slices->value("skipped", Json::array()))
      rows.push_back({s.value("shot", std::string()), std::to_string(s.value("board", -1)), s.value("reason", std::string())});
  report->Heading(Format("Rejected shots and skipped slices (%zu)", rows.size()));
  if (rows.empty()) return report->Paragraph("None.");
  std::map<std::string, std::pair<int, std::set<std::string>>> groups;  // kind -> count, boards
  for (const auto& row : rows) {
    auto& [count, boards] = groups[ReasonKind(row[2])];
    ++count;
    if (!row[1].empty()) boards.insert(row[1]);
  }
  std::vector<std::pair<std::string, std::pair<int, std::set<std::string>>>> by_count(groups.begin(), groups.end());
  std::stable_sort(by_count.begin(), by_count.end(), [](const auto& a, const auto& b) { return a.second.first > b.second.first; });
  std::vector<std::vector<std::string>> grouped;
  for (const auto& [kind, group] : by_count) {
    std::string boards;
    for (const std::string& b : group.second) boards += (boards.empty() ? "" : ", ") + b;
    grouped.push_back({kind, std::to_string(group.first), boards});
  }
  report->Table({"reason", "count", "boards"}, grouped);
  report->FoldedTable(Format("Every one of the %zu, with its shot", rows.size()), {"shot", "board", "reason"}, rows);
}

}  // namespace

Status WriteProcessReport(const fs::path& session, const std::vector<StageOutcome>& outcomes) {
  Report report("mesocap process: " + fs::absolute(session).filename().string());
  report.Paragraph("Every stage of the session's processing, from the shots to the exports. A stage whose inputs and "
                   "options did not change since it last ran was skipped (SESSION/stages.json).");
  std::vector<std::vector<std::string>> rows;
  for (const StageOutcome& o : outcomes)
    rows.push_back({o.name, o.status, Format("%.1f", o.seconds), o.summary.brief, std::to_string(o.summary.warnings.size())});
  report.Table({"stage", "status", "seconds", "outputs", "warnings"}, rows);
  report.Heading("Calibration");
  AddCalibrationTables(session, &report);
  if (fs::exists(session / "calibration" / kFlashPositionsPlot))
    report.Picture("calibration/" + std::string(kFlashPositionsPlot),
                   "Every calibrated flash position around the target (orange), with the boards' patches, the balls and "
                   "the camera, from above and from the side (top board's frame)");
  if (fs::exists(session / "calibration" / "lights.png"))
    report.Picture("calibration/lights.png", "Flash directions seen from the top board (centre: zenith)");
  if (fs::exists(session / "calibration" / "intrinsics_residuals.png"))
    report.Picture("calibration/intrinsics_residuals.png", "Checkerboard corner residuals of the camera calibration");
  report.Heading("Rejected shots, skipped slices and other warnings");
  std::vector<std::vector<std::string>> warnings;
  for (const StageOutcome& o : outcomes)
    for (const std::string& w : o.summary.warnings) warnings.push_back({o.name, w});
  if (warnings.empty()) report.Paragraph("None.");
  else report.Table({"stage", "warning"}, warnings);
  MESOCAP_RETURN_IF_ERROR(AddLightCoverage(session, &report));
  AddRejectedItems(session, &report);
  report.Heading("Results");
  if (fs::exists(session / "export" / "previews" / "ptm_relit.jpg"))
    report.Picture("export/previews/ptm_relit.jpg", "The top board's PTM (export/material.ptm) relit under three lights");
  if (auto top = TopBoardOfSession(session); top.ok()) {
    const fs::path residual = BoardPtmResidualFile(session, *top, ".png");
    if (fs::exists(residual))
      report.Picture(fs::relative(residual, session).generic_string(),
                     "The top board's PTM fit error per texel (RMS residual x 10: white is 0.1 or more)");
  }
  if (fs::exists(session / "export" / "previews" / "btf_slices.jpg"))
    report.Picture("export/previews/btf_slices.jpg", "Slices of the reconstructed BTF (export/btf/), one exposure");
  if (auto fit = ReadJsonFile(session / "export" / "gltf" / "fit.json"); fit.ok()) {
    report.Paragraph(Format("export/gltf/material.gltf: a glTF 2.0 metallic-roughness material fitted per texel to the "
                            "reconstructed BTF (%d slices, median relative error %.1f%%, %.1f s), on a preview quad and "
                            "sphere.",
                            fit->value("slices_used", 0), 100 * fit->value("median_relative_error", 0.0),
                            fit->value("seconds", 0.0)));
    report.Picture("export/gltf/fit_error.png", "The glTF fit's relative error per texel (black 0, white 50% or more)");
    if (fs::exists(session / "export" / "previews" / "material_sphere.jpg")) {
      report.Picture("export/previews/material_sphere.jpg", "The glTF material on a sphere under three lights");
      report.Picture("export/previews/material_cloth.jpg", "The glTF material on a draped sheet under the same lights");
    }
  }
  if (auto synth = ReadJsonFile(session / "synth" / "report.json"); synth.ok()) {
    const Json output = synth->value("output", Json::object());
    report.Paragraph(Format("synth/: the reconstructed BTF enlarged by %s to %dx%d texels (export/gltf_synth/ carries the "
                            "glTF material through the same map).",
                            synth->value("method", std::string("?")).c_str(), output.value("width", 0), output.value("height", 0)));
    for (int k = 1; k <= 3; ++k)
      if (const std::string name = Format("synth/preview_light%d.png", k); fs::exists(session / name))
        report.Picture(name, Format("The enlarged BTF under light %d", k));
    if (fs::exists(session / "synth" / "patches.png"))
      report.Picture("synth/patches.png", "Where each part of the enlarged material comes from (one colour per patch)");
  }
  MESOCAP_RETURN_IF_ERROR(AddViewer(session, &report));
  report.Paragraph("Files: calibration/ (rig.json, report.json), slices/ (measured BTF slices, index.json, board_BB.lp), "
                   "ptm/ (one PTM per board), btf/ (the reconstructed BTF), export/ (material.ptm, lp/, btf/, gltf/, previews/). "
                   "Formats: docs/formats.md.");
  return report.Write(session);
}


}  // namespace mesocap::app
