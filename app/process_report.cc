// SESSION/report.html of `mesocap process` (app/process.h): the stage table, calibration
// tables and plots, every warning and rejected item, the results' pictures and the WebGL viewer.
#include "app/process.h"

#include <algorithm>
#include <cctype>
#include <map>
#include <optional>
#include <set>

#include "app/session_stages.h"
#include "app/synth_output.h"
#include "calib/calibrate.h"
#include "core/atomic_file.h"
#include "core/image_io.h"
#include "core/json.h"
#include "core/session_layout.h"
#include "core/slice_index.h"
#include "core/text_format.h"
#include "export/ggx_fit.h"
#include "export/previews.h"
#include "export/report.h"

namespace mesocap::app {

namespace fs = std::filesystem;

namespace {

// The viewer the export stage built (export/previews/viewer.html), placed in the page.
Status AddViewer(const SessionLayout& session, Report* report) {
  const fs::path fragment = session.exports().previews().viewer();
  if (!fs::exists(fragment)) return Status::Ok();
  auto html = ReadTextFile(fragment);
  if (!html.ok()) return html.status();
  report->Heading("Relight it");
  report->Html(*html, session.report_html().filename().string() +
                          " relights the top board's PTM and the reconstructed BTF here, in WebGL.");
  return Status::Ok();
}

// Which light directions each board measured (its own frame): where the reconstruction has
// data and where it extrapolates. The picture goes in SESSION/report_files/, beside the report
// and outside every stage's outputs.
Status AddLightCoverage(const SessionLayout& session, const SliceIndex& index, Report* report) {
  std::map<int, std::vector<Eigen::Vector3d>> lights;
  for (const SliceIndexEntry& e : index.slices) lights[e.board].push_back(e.light);
  std::vector<Image> plots;
  std::vector<std::string> labels;
  for (const auto& [board, dirs] : lights) {
    plots.push_back(HemispherePlot(dirs, 240, Format("board %d", board)));
    labels.push_back(Format("board %d: %zu lights", board, dirs.size()));
  }
  if (plots.empty()) return Status::Ok();
  std::error_code ec;
  fs::create_directories(session.report_files(), ec);
  if (ec) return Status::Error(session.report_files().string() + ": cannot create: " + ec.message());
  MESOCAP_RETURN_IF_ERROR(WriteImage(session.light_coverage_plot(), ContactSheet(plots, labels, 5, 200),
                                     {.format = PixelFormat::kUint8Srgb}));
  report->Heading("Light coverage");
  report->Paragraph("The flash directions each board measured, in its own frame (centre: its normal; rings at 30, 60 and "
                    "90 deg). The reconstruction interpolates between them and extrapolates beyond: a tilted board "
                    "never sees the flash from below its slope.");
  report->Picture(session.Relative(session.light_coverage_plot()), "Measured light directions per board");
  return Status::Ok();
}

// A stage's record that is there but cannot be read: said in the report, not passed over.
void SayUnreadable(const Status& status, Report* report) {
  report->Paragraph("Could not be read: " + status.message());
}

// The camera and every board's pose with its uncertainty, from calibration/rig.json.
void AddCalibrationTables(const SessionLayout& session, Report* report) {
  if (!fs::exists(session.calibration().rig())) return;  // the stage table says why
  auto rig = LoadSessionCalibration(session.root());
  if (!rig.ok()) return SayUnreadable(rig.status(), report);
  const CameraModel& camera = rig->camera;
  report->Table({"width", "height", "fx px", "fy px", "cx px", "cy px"},
                {{std::to_string(camera.width), std::to_string(camera.height), Format("%.1f", camera.K(0, 0)),
                  Format("%.1f", camera.K(1, 1)), Format("%.1f", camera.K(0, 2)), Format("%.1f", camera.K(1, 2))}});
  std::vector<std::vector<std::string>> rows;
  for (const BoardPose& b : rig->boards) {
    if (!b.found) {
      rows.push_back({std::to_string(b.id), "not posed: " + b.why_not, "", "", "", ""});
      continue;
    }
    rows.push_back({std::to_string(b.id), std::to_string(b.shots_seen), std::to_string(b.corners_used),
                    Format("%.3f", b.rms_reprojection_px), Format("%.4f", b.rotation_stddev_deg),
                    Format("%.3f", b.translation_stddev_mm)});
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

// Every rejected calibration item and every skipped (board, shot) of `slices` (when the session
// has an index): grouped by reason with counts, the full list folded away under them.
void AddRejectedItems(const SessionLayout& session, const std::optional<StatusOr<SliceIndex>>& slices, Report* report) {
  std::vector<std::vector<std::string>> rows;
  std::vector<Status> unreadable;
  const CalibrationFolder calibration = session.calibration();
  if (fs::exists(calibration.report())) {
    auto rejected = ReadJsonRecord(calibration.report(), CalibrationResult::RejectedFromReportJson);
    if (!rejected.ok()) unreadable.push_back(rejected.status());
    else
      for (const std::string& r : *rejected) rows.push_back({calibration.root.filename().string(), "", r});
  }
  if (slices && !slices->ok()) unreadable.push_back(slices->status());
  else if (slices)
    for (const SkippedSlice& s : (*slices)->skipped) rows.push_back({s.shot, std::to_string(s.board), s.reason});
  report->Heading(Format("Rejected shots and skipped slices (%zu)", rows.size()));
  for (const Status& status : unreadable) SayUnreadable(status, report);
  if (rows.empty()) return report->Paragraph(unreadable.empty() ? "None." : "None readable.");
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

// A light circling a dressed mesh: its frames shown in turn (report.md lists the first).
void AddLightSweep(const SessionLayout& session, const DecorateFolder& folder, Report* report) {
  std::vector<std::string> frames;
  for (int k = 0; fs::exists(folder.sweep_frame(k)); ++k) frames.push_back(session.Relative(folder.sweep_frame(k)));
  if (frames.empty()) return;
  std::string list;
  for (const std::string& f : frames) list += (list.empty() ? "\"" : ", \"") + HtmlEscape(f) + "\"";
  const std::string id = "sweep-" + HtmlEscape(folder.root.filename().string());
  report->Html("<figure><img id=\"" + id + "\" src=\"" + HtmlEscape(frames[0]) + "\" alt=\"light sweep\"><figcaption>The light circling the " +
                   "dressed mesh (" + std::to_string(frames.size()) + " frames): the mesostructure stays in place</figcaption></figure>" +
                   "<script>(function(){var f=[" + list + "],i=0,e=document.getElementById(\"" + id +
                   "\");setInterval(function(){i=(i+1)%f.length;e.src=f[i];},250);})();</script>",
               "A light sweep of the dressed mesh: " + frames[0] + " and the frames after it.");
}

// process --decorate's meshes: each one's figures, previews and light sweep.
void AddDressedMeshes(const SessionLayout& session, Report* report) {
  std::error_code ec;
  if (!fs::is_directory(session.decorate_root(), ec)) return;
  std::vector<fs::path> folders;
  for (const auto& entry : fs::directory_iterator(session.decorate_root(), ec))
    if (entry.is_directory()) folders.push_back(entry.path());
  std::sort(folders.begin(), folders.end());
  for (const fs::path& root : folders) {
    const DecorateFolder folder{root};
    auto j = ReadJsonFile(folder.report());
    if (!j.ok()) {
      SayUnreadable(j.status(), report);
      continue;
    }
    try {
      const Json& q = (*j)["quality"];
      const std::string how =
          (*j)["method"] == "quilt"
              ? Format("by graphcut quilting on its %d texel atlas (%s): %d patches, %d of them across charts",
                       (*j)["gltf"]["atlas_size"].get<int>(), (*j)["gltf"]["atlas"].get<std::string>().c_str(),
                       q["patches"].get<int>(), q["chart_crossing_patches"].get<int>())
              : Format("by surface textons: %.1f%% of its edges inside patches, %.2f%% repeats",
                       100 * q["coherent_edges"].get<double>(), 100 * q["repeats"].get<double>());
      report->Paragraph(Format("%s/: %s (%d vertices) dressed in the reconstructed BTF %s; a glTF asset in %s.",
                               session.Relative(root).c_str(), root.filename().string().c_str(), (*j)["mesh"]["vertices"].get<int>(),
                               how.c_str(), session.Relative(folder.gltf().material()).c_str()));
    } catch (const std::exception& e) {
      SayUnreadable(Status::Error(folder.report().string() + ": " + e.what()), report);
      continue;
    }
    for (int k = 0; k < 3; ++k)
      if (fs::exists(folder.preview_light(k)))
        report->Picture(session.Relative(folder.preview_light(k)), Format("%s under light %d, with cast shadows", root.filename().string().c_str(), k + 1));
    AddLightSweep(session, folder, report);
  }
}

// The pictures and figures of the results: the PTM (of the top board in `slices`, when read), the
// BTF, the glTF material, the synthesis.
void AddResults(const SessionLayout& session, const SliceIndex* slices, Report* report) {
  const auto picture = [&](const fs::path& file, const std::string& caption) {
    if (fs::exists(file)) report->Picture(session.Relative(file), caption);
  };
  const ExportFolder exports = session.exports();
  const PreviewsFolder previews = exports.previews();
  const std::string ptm_export = session.Relative(exports.material_ptm());
  picture(previews.ptm_relit(), "The top board's PTM (" + ptm_export + ") relit under three lights");
  if (const int top = slices ? TopBoardOf(*slices) : -1; top >= 0)
    picture(session.ptm().board_residual(top, ".png"),
            "The top board's PTM fit error per texel (RMS residual x 10: white is 0.1 or more)");
  picture(previews.btf_slices(), "Slices of the reconstructed BTF (" + session.Relative(exports.btf().root) + "/), one exposure");
  const GltfFolder gltf = exports.gltf();
  if (fs::exists(gltf.fit_report())) {
    auto fit = ReadJsonRecord(gltf.fit_report(), GgxMaterialMaps::FiguresFromJson);
    if (!fit.ok()) {
      SayUnreadable(fit.status(), report);
    } else {
      report->Paragraph(Format("%s: a glTF 2.0 metallic-roughness material fitted per texel to the reconstructed BTF (%d "
                               "slices, median relative error %.1f%%, %.1f s), on a preview quad and sphere.",
                               session.Relative(gltf.material()).c_str(), fit->slices_used,
                               100 * fit->median_relative_error, fit->seconds));
      picture(gltf.fit_error(".png"), "The glTF fit's relative error per texel (black 0, white 50% or more)");
      picture(previews.material_sphere(), "The glTF material on a sphere under three lights");
      picture(previews.material_cloth(), "The glTF material on a draped sheet under the same lights");
    }
  }
  const SynthFolder synth = session.synth();
  if (fs::exists(synth.report())) {
    auto summary = ReadSynthReportSummary(synth);
    if (!summary.ok()) return SayUnreadable(summary.status(), report);
    report->Paragraph(Format("%s/: the reconstructed BTF enlarged by %s to %dx%d texels (%s/ carries the glTF material "
                             "through the same map).",
                             session.Relative(synth.root).c_str(), summary->method.c_str(), summary->width,
                             summary->height, session.Relative(exports.gltf_synth().root).c_str()));
    for (int k = 1; k <= 3; ++k) picture(synth.preview_light(k), Format("The enlarged BTF under light %d", k));
    picture(synth.patches(), "Where each part of the enlarged material comes from (one colour per patch)");
  }
  AddDressedMeshes(session, report);
}

}  // namespace

Status WriteProcessReport(const fs::path& session_root, const std::vector<StageOutcome>& outcomes) {
  const SessionLayout session(session_root);
  Report report("mesocap process: " + fs::absolute(session_root).filename().string());
  report.Paragraph("Every stage of the session's processing, from the shots to the exports. A stage whose inputs and "
                   "options did not change since it last ran was skipped (SESSION/" +
                   session.Relative(session.stage_cache()) + ").");
  std::vector<std::vector<std::string>> rows;
  for (const StageOutcome& o : outcomes)
    rows.push_back({o.name, o.status, Format("%.1f", o.seconds), o.summary.brief, std::to_string(o.summary.warnings.size())});
  report.Table({"stage", "status", "seconds", "outputs", "warnings"}, rows);
  report.Heading("Calibration");
  AddCalibrationTables(session, &report);
  const CalibrationFolder calibration = session.calibration();
  for (const auto& [file, caption] :
       {std::pair{calibration.flash_positions_plot(),
                  std::string("Every calibrated flash position around the target (orange), with the boards' patches, the "
                              "balls and the camera, from above and from the side (top board's frame)")},
        std::pair{calibration.lights_plot(), std::string("Flash directions seen from the top board (centre: zenith)")},
        std::pair{calibration.intrinsics_plot(), std::string("Checkerboard corner residuals of the camera calibration")}})
    if (fs::exists(file)) report.Picture(session.Relative(file), caption);
  report.Heading("Rejected shots, skipped slices and other warnings");
  std::vector<std::vector<std::string>> warnings;
  for (const StageOutcome& o : outcomes)
    for (const std::string& w : o.summary.warnings) warnings.push_back({o.name, w});
  if (warnings.empty()) report.Paragraph("None.");
  else report.Table({"stage", "warning"}, warnings);
  // The slice index, read once for the three sections that use it.
  std::optional<StatusOr<SliceIndex>> slices;
  if (fs::exists(session.slices().index())) slices = ReadSliceIndex(session.slices().index());
  const SliceIndex* index = slices && slices->ok() ? &**slices : nullptr;
  if (index) MESOCAP_RETURN_IF_ERROR(AddLightCoverage(session, *index, &report));
  AddRejectedItems(session, slices, &report);
  report.Heading("Results");
  AddResults(session, index, &report);
  MESOCAP_RETURN_IF_ERROR(AddViewer(session, &report));
  report.Paragraph("Every file of the session: docs/formats.md (`mesocap layout " + session_root.string() +
                   "` prints their paths).");
  return report.Write(session_root);
}

}  // namespace mesocap::app
