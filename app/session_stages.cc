#include "app/session_stages.h"

#include <algorithm>
#include <cstdio>
#include <map>

#include "app/board_lights.h"
#include "app/btf_folder.h"
#include "app/rig_plot.h"
#include "calib/intrinsics.h"
#include "calib/intrinsics_plot.h"
#include "core/atomic_file.h"
#include "core/directions.h"
#include "core/image_io.h"
#include "core/progress.h"
#include "core/provenance.h"
#include "core/session.h"
#include "core/session_layout.h"
#include "core/slice_index.h"
#include "core/text_format.h"
#include "export/previews.h"
#include "formats/ptm_file.h"

namespace mesocap::app {

namespace fs = std::filesystem;

fs::path SessionLayoutFile(const fs::path& session, const fs::path& layout_file) {
  return layout_file.empty() ? SessionLayout(session).rig_layout() : layout_file;
}

StatusOr<RigLayout> LoadSessionLayout(const fs::path& session, const fs::path& layout_file) {
  const fs::path file = SessionLayoutFile(session, layout_file);
  auto j = ReadJsonFile(file);
  if (!j.ok()) return Status::Error(j.status().message() + " (give the rig's layout with --layout)");
  auto layout = RigLayout::FromJson(*j);
  if (!layout.ok()) return Status::Error(file.string() + ": " + layout.status().message());
  return layout;
}

StatusOr<CalibrationResult> LoadSessionCalibration(const fs::path& session) {
  const fs::path rig_file = SessionLayout(session).calibration().rig();
  if (!fs::exists(rig_file))
    return Status::Error(rig_file.string() + " not found: run `mesocap calibrate " + session.string() + "` first");
  return ReadJsonRecord(rig_file, CalibrationResult::FromRigJson);
}

StatusOr<CameraModel> CameraFor(const CalibrateStageOptions& o, const RigLayout& layout, Json* intrinsics_report,
                                Image* residual_plot) {
  if (!o.camera_file.empty()) {
    auto j = ReadJsonFile(o.camera_file);
    if (!j.ok()) return j.status();
    try {
      return CameraModel::FromJson(j->contains("camera") ? j->at("camera") : *j);
    } catch (const std::exception& e) {
      return Status::Error(o.camera_file.string() + ": not a camera file: " + e.what());
    }
  }
  const fs::path& session_dir = o.calibrate.session;
  auto session = Session::Open(session_dir);
  if (!session.ok()) return session.status();
  std::vector<fs::path> images;
  for (const auto& r : session->ShotsOfKind("calib")) images.push_back(session_dir / r.file);
  if (images.empty())
    return Status::Error(session_dir.string() + ": no checkerboard shots (" + FolderName(SessionLayout(session_dir).calib()) +
                         ") and no --camera file");
  IntrinsicsOptions io;
  io.cols = layout.checker_cols;
  io.rows = layout.checker_rows;
  io.square_m = layout.checker_square_m;
  ProgressBar bar("intrinsics", o.progress);
  auto result = CalibrateIntrinsics(images, io, bar.AsCallback());
  if (!result.ok()) return result.status();
  *intrinsics_report = result->ToJson();
  *residual_plot = PlotIntrinsicsResiduals(*result);
  std::fprintf(stderr, "intrinsics: %s\n", result->Brief().c_str());
  return result->camera;
}

namespace {

// Flash directions seen from the most head-on board (the top of the pyramid).
Image LightsPlot(const CalibrationResult& result) {
  const BoardPose* top = TopBoardPose(result);
  if (!top) return Image();
  std::vector<Eigen::Vector3d> dirs;
  for (const ShotCalibration& shot : result.shots)
    if (shot.light.ok) dirs.push_back(top->R.transpose() * (shot.light.light_m - top->t));
  return HemispherePlot(dirs, 420, "flash directions, board " + std::to_string(top->id) + " frame");
}

Status WritePng(const fs::path& file, const Image& image) {
  return WriteImage(file, image, {.format = PixelFormat::kUint8Srgb});
}

}  // namespace

StatusOr<StageSummary> RunCalibrateStage(const CalibrateStageOptions& o) {
  if (std::string why = o.calibrate.Check(); !why.empty()) return Status::Error(why);
  // The session first: a wrong path is named as such, not as a missing layout inside it.
  if (auto session = Session::Open(o.calibrate.session); !session.ok()) return session.status();
  auto layout = LoadSessionLayout(o.calibrate.session, o.layout_file);
  if (!layout.ok()) return layout.status();
  Json intrinsics_report = Json::object();
  Image residual_plot;
  auto camera = CameraFor(o, *layout, &intrinsics_report, &residual_plot);
  if (!camera.ok()) return camera.status();
  ProgressBar bar("calibrate", o.progress);
  auto result = CalibrateSession(o.calibrate, *layout, *camera, bar.AsCallback());
  if (!result.ok()) return result.status();
  // calibration/ appears whole: a re-run swaps the new folder in only once every file is written.
  auto staging = StagingFolder::Begin(SessionLayout(o.calibrate.session).calibration().root);
  if (!staging.ok()) return staging.status();
  const CalibrationFolder out{staging->path()};
  Json rig = result->RigJson();
  rig["provenance"] = MakeProvenance({{"session", o.calibrate.session.string()}, {"pose_shots", o.calibrate.pose_shots},
                                      {"camera_file", o.camera_file.string()}, {"layout", o.layout_file.string()}});
  Json report = result->ReportJson();
  report["intrinsics"] = intrinsics_report;
  MESOCAP_RETURN_IF_ERROR(WriteJsonFile(out.rig(), rig));
  MESOCAP_RETURN_IF_ERROR(WriteJsonFile(out.report(), report));
  if (!residual_plot.empty()) MESOCAP_RETURN_IF_ERROR(WritePng(out.intrinsics_plot(), residual_plot));
  if (const Image plot = LightsPlot(*result); !plot.empty()) MESOCAP_RETURN_IF_ERROR(WritePng(out.lights_plot(), plot));
  if (const Image plot = FlashPositionsPlot(*result, *layout); !plot.empty())
    MESOCAP_RETURN_IF_ERROR(WritePng(out.flash_positions_plot(), plot));
  MESOCAP_RETURN_IF_ERROR(staging->Publish(/*replace=*/true));
  StageSummary summary;
  summary.brief = result->Brief();
  summary.warnings = result->rejected;
  summary.report = {{"usable_shots", result->usable_shots()}, {"shots", result->shots.size()},
                    {"rejected", result->rejected.size()}};
  if (intrinsics_report.contains("report"))
    summary.report["intrinsics_rms_px"] = intrinsics_report["report"]["rms_reprojection_px"];
  return summary;
}

namespace {

// A note when the shots are JPEGs that keep colour at half resolution: the slices then lose
// colour detail finer than two pixels, which the statistical BTF's colour needs (on a virtual
// weave session, 100 shots: chromaticity won on 31% of held-out pairs from JPEG shots, 83% from
// 16-bit PNG; bench/calibrated_session_bench.sh), most on the tilted boards, whose patches span
// the fewest pixels. Resampling restores what follows the brightness (core/chroma_detail.h);
// reconstruct still takes the colour from the top view.
std::string ColourResolutionNote(const ResampleReport& slices) {
  if (!slices.chroma_subsampled_shots) return "";
  const std::string loss = slices.chroma_detail_restored
                               ? "colour detail finer than 2 pixels was restored from the brightness where it follows it"
                               : "the slices lose colour detail finer than 2 pixels";
  return "the shots are JPEGs with colour at half resolution (" + fs::path(slices.slices.front().shot).filename().string() +
         "): " + loss + ", and reconstruct takes the colour from the top board "
         "(--chroma-from-views overrides); shoot RAW or 16-bit TIFF where the material's colour matters";
}

}  // namespace

StatusOr<StageSummary> RunResampleStage(const fs::path& session, const fs::path& layout_file,
                                        const ResampleOptions& options, bool progress) {
  if (std::string why = options.Check(); !why.empty()) return Status::Error(why);
  auto layout = LoadSessionLayout(session, layout_file);
  if (!layout.ok()) return layout.status();
  auto calibration = LoadSessionCalibration(session);
  if (!calibration.ok()) return calibration.status();
  ProgressBar bar("resample", progress);
  auto slices = ResampleSession(options, session, *layout, *calibration, bar.AsCallback(), WriteBoardLightFiles);
  if (!slices.ok()) return slices.status();
  StageSummary summary;
  summary.brief = slices->Brief();
  std::map<std::string, int> skipped_by_reason;  // the full list is in index.json
  for (const auto& s : slices->skipped)
    ++skipped_by_reason[s.reason.substr(0, std::min(s.reason.find(" ("), s.reason.find(" by ")))];
  for (const auto& [reason, count] : skipped_by_reason)
    summary.warnings.push_back(Format("skipped %d: %s", count, reason.c_str()));
  if (std::string note = ColourResolutionNote(*slices); !note.empty()) summary.warnings.push_back(note);
  summary.report = {{"slices", slices->slices.size()}, {"skipped", slices->skipped.size()},
                    {"slice_size", slices->slice_size}};
  return summary;
}

int TopBoardOf(const SliceIndex& index) {
  std::map<int, std::pair<double, int>> theta_o;  // board -> (sum, count)
  for (const SliceIndexEntry& e : index.slices) {
    theta_o[e.board].first += e.theta_o_deg;
    ++theta_o[e.board].second;
  }
  int best = -1;
  double best_theta = 1e9;
  for (const auto& [board, sum] : theta_o)
    if (sum.first / sum.second < best_theta) best = board, best_theta = sum.first / sum.second;
  return best;
}

StatusOr<int> TopBoardOfSession(const fs::path& session) {
  const fs::path index_file = SessionLayout(session).slices().index();
  auto index = ReadSliceIndex(index_file);
  if (!index.ok()) return index.status();
  const int best = TopBoardOf(*index);
  if (best < 0) return Status::Error(index_file.string() + ": lists no slices");
  return best;
}

StatusOr<StageSummary> RunPtmStage(const fs::path& session, const fs::path& layout_file, const PtmStageOptions& options,
                                   bool progress) {
  auto layout = LoadSessionLayout(session, layout_file);
  if (!layout.ok()) return layout.status();
  const fs::path index_file = SessionLayout(session).slices().index();
  auto index = ReadSliceIndex(index_file);
  if (!index.ok()) return index.status();
  std::map<int, std::vector<size_t>> by_board;
  for (size_t k = 0; k < index->slices.size(); ++k) by_board[index->slices[k].board].push_back(k);

  auto staging = StagingFolder::Begin(SessionLayout(session).ptm().root);
  if (!staging.ok()) return staging.status();
  const PtmFolder out{staging->path()};
  StageSummary summary;
  Json boards = Json::array();
  ProgressBar bar("fit-ptm", progress);
  int done = 0, fitted = 0;
  for (const auto& [board, members] : by_board) {
    if (!ReportProgress(bar.AsCallback(), done++, int(by_board.size()), Format("board %d", board)))
      return Status::Cancelled();
    const LayoutBoard* layout_board = nullptr;
    for (const LayoutBoard& b : layout->boards)
      if (b.id == board) layout_board = &b;
    if (!layout_board) return Status::Error(index_file.string() + ": board " + std::to_string(board) + " is not in the rig layout");
    if (int(members.size()) < options.min_slices) {
      summary.warnings.push_back(Format("board %d: %zu slices, fewer than the %d a PTM needs", board, members.size(),
                                        options.min_slices));
      continue;
    }
    std::vector<Image> images;
    std::vector<Eigen::Vector3d> lights_m;
    for (size_t k : members) {
      const SliceIndexEntry& e = index->slices[k];
      auto image = ReadImage(e.file);
      if (!image.ok()) return image.status();
      images.push_back(std::move(*image));
      if (!(e.light_distance_m > 0))
        return Status::Error(index_file.string() + ": slice " + e.file.filename().string() + " has no light_distance_m");
      lights_m.push_back(e.light_distance_m * e.light);
    }
    PtmFitOptions fit;
    fit.format = options.format;
    PtmFitReport report;
    Image residual;
    auto ptm = FitPtmPerPixelLights(images, PointLightDirections(lights_m, images.front().width(), layout_board->patch_m),
                                    fit, &report, nullptr, &residual);
    if (!ptm.ok()) {
      summary.warnings.push_back(Format("board %d: no PTM: %s", board, ptm.status().message().c_str()));
      continue;
    }
    const fs::path file = out.board_ptm(board);
    MESOCAP_RETURN_IF_ERROR(WritePtmFile(file, *ptm));
    // The fit's error map: RMS residual per texel, as values (EXR) and to see (PNG: x 10, so white
    // is a residual of 0.1, a tenth of a white surface's value).
    MESOCAP_RETURN_IF_ERROR(WriteImage(out.board_residual(board, ".exr"), residual, {.format = PixelFormat::kHalf}));
    MESOCAP_RETURN_IF_ERROR(WritePng(out.board_residual(board, ".png"), GreyPicture(residual, 10)));
    boards.push_back({{"board", board}, {"file", file.filename().string()}, {"lights", report.num_lights},
                      {"rms_residual", report.rms_residual}, {"width", report.width}, {"height", report.height},
                      {"warnings", report.warnings}});
    ++fitted;
  }
  ReportProgress(bar.AsCallback(), done, int(by_board.size()), "");
  if (fitted == 0) return Status::Error(index_file.string() + ": no board has slices enough for a PTM");
  Json report = {{"format", PtmFormatToString(options.format)}, {"boards", boards}};
  report["provenance"] = MakeProvenance({{"session", session.string()}, {"format", PtmFormatToString(options.format)}});
  MESOCAP_RETURN_IF_ERROR(WriteJsonFile(out.report(), report));
  MESOCAP_RETURN_IF_ERROR(staging->Publish(/*replace=*/true));
  summary.brief = Format("%d of %zu boards fitted (%s, per-pixel flash directions)", fitted, by_board.size(),
                         PtmFormatToString(options.format).c_str());
  summary.report = {{"boards_fitted", fitted}};
  return summary;
}

Json ReconstructStageOptions::ToJson() const {
  Json settings = method.ToJson();
  settings.update({{"size", slices.size}, {"grid", grid}, {"pixel_only", pixel_only}});
  return settings;
}

StatusOr<SliceSetOptions> ReconstructStageOptions::SliceOptions() const {
  if (GridPairs(grid).empty()) return Status::Error("the BTF grid must be bonn or coarse, not '" + grid + "'");
  SliceSetOptions slice_options = slices;
  slice_options.btf.match_subbands = !pixel_only;
  if (!method.ApplyTo(&slice_options)) return Status::Error("unknown BTF colour space '" + method.colour_space + "'");
  if (!slice_options.Check()) return Status::Error("the BTF size must be a power of two");
  return slice_options;
}

Json ReconstructStageOptions::Provenance(const fs::path& session) const {
  Json provenance = ToJson();
  provenance["index"] = SessionLayout(session).slices().index().string();
  return provenance;
}

StatusOr<fs::path> ReconstructStageIndex(const fs::path& session) {
  const fs::path index = SessionLayout(session).slices().index();
  if (!fs::exists(index))
    return Status::Error(index.string() + " not found: run `mesocap calibrate " + session.string() + "` first");
  return index;
}

StageSummary ReconstructStageSummary(const BtfFolderReport& written, const Json& header, const std::string& grid) {
  StageSummary summary;
  const int size = header.value("width", 0), views = header.value("views_measured", 0);
  const bool chroma_from_top = header.value("chroma_from_top", false);
  summary.brief = Format("%d slices (%dx%d, grid %s) from %d measured slices in %d views, %.1f ms per slice%s",
                         written.slices, size, header.value("height", 0), grid.c_str(), header.value("slices_used", 0),
                         views, written.ms_per_slice, chroma_from_top ? ", colour from the top view" : "");
  for (const Json& s : header.value("skipped", Json::array())) summary.warnings.push_back("skipped " + s.get<std::string>());
  for (const Json& w : header.value("warnings", Json::array())) summary.warnings.push_back(w.get<std::string>());
  summary.report = {{"slices", written.slices}, {"size", size}, {"views", views},
                    {"ms_per_slice", written.ms_per_slice}, {"chroma_from_top", chroma_from_top}};
  return summary;
}

StatusOr<StageSummary> RunReconstructStage(const fs::path& session, const ReconstructStageOptions& options, bool progress) {
  auto slice_options = options.SliceOptions();
  if (!slice_options.ok()) return slice_options.status();
  auto index = ReconstructStageIndex(session);
  if (!index.ok()) return index.status();
  SliceSetReport loaded;
  ProgressBar load_bar("statistics", progress);
  auto btf = LoadStatisticalBtf(*index, *slice_options, &loaded, load_bar.AsCallback());
  if (!btf.ok()) return btf.status();
  auto staging = StagingFolder::Begin(SessionLayout(session).btf().root);
  if (!staging.ok()) return staging.status();
  ProgressBar bar("reconstruct", progress);
  auto reconstructed = ReconstructPairs(*btf, GridPairs(options.grid), options.pixel_only, slice_options->btf.num_threads,
                                        staging->path(), bar.AsCallback());
  if (!reconstructed.ok()) return reconstructed.status();
  const Json header = BtfIndexHeader(*btf, loaded);
  auto written = WriteBtfIndex(staging->path(), header, *reconstructed, options.Provenance(session));
  if (!written.ok()) return written.status();
  MESOCAP_RETURN_IF_ERROR(staging->Publish(/*replace=*/true));
  return ReconstructStageSummary(*written, header, options.grid);
}

}  // namespace mesocap::app
