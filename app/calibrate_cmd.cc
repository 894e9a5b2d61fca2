// mesocap calibrate SESSION: intrinsics (from the session's checkerboard shots or --camera),
// board poses, balls, flash position and power per shot -> SESSION/calibration/; then every
// lit board patch of every usable shot resampled into a BTF slice -> SESSION/slices/.
#include <cstdio>
#include <map>
#include <memory>

#include "app/board_lights.h"
#include "app/commands.h"
#include "calib/intrinsics_plot.h"
#include "core/image_io.h"
#include "export/previews.h"
#include "calib/calibrate.h"
#include "calib/intrinsics.h"
#include "calib/resample.h"
#include "core/atomic_file.h"
#include "core/provenance.h"
#include "core/session.h"

namespace mesocap::app {
namespace {

namespace fs = std::filesystem;

struct CalibrateArgs {
  CalibrateOptions options;
  ResampleOptions resample;
  bool no_resample = false, no_brdf_smoothing = false;
  fs::path camera_file, layout_file;
  bool no_progress = false;
};

StatusOr<CameraModel> CameraFor(const CalibrateArgs& a, const RigLayout& layout, Json* intrinsics_report, Image* residual_plot) {
  if (!a.camera_file.empty()) {
    auto j = ReadJsonFile(a.camera_file);
    if (!j.ok()) return j.status();
    try {
      return CameraModel::FromJson(j->contains("camera") ? j->at("camera") : *j);
    } catch (const std::exception& e) {
      return Status::Error(a.camera_file.string() + ": not a camera file: " + e.what());
    }
  }
  auto session = Session::Open(a.options.session);
  if (!session.ok()) return session.status();
  std::vector<fs::path> images;
  for (const auto& r : session->ShotsOfKind("calib")) images.push_back(a.options.session / r.file);
  if (images.empty())
    return Status::Error(a.options.session.string() + ": no checkerboard shots (calib/) and no --camera file");
  IntrinsicsOptions io;
  io.cols = layout.checker_cols;
  io.rows = layout.checker_rows;
  io.square_m = layout.checker_square_m;
  ProgressBar bar("intrinsics", !a.no_progress);
  auto result = CalibrateIntrinsics(images, io, bar.AsCallback());
  if (!result.ok()) return result.status();
  *intrinsics_report = result->ToJson();
  if (residual_plot) *residual_plot = PlotIntrinsicsResiduals(*result);
  std::fprintf(stderr, "intrinsics: %s\n", result->Brief().c_str());
  return result->camera;
}

int Run(CalibrateArgs& a) {
  if (std::string why = a.options.Check(); !why.empty()) return Fail("calibrate", why, kExitUsage);
  a.resample.brdf_smoothing = !a.no_brdf_smoothing;
  a.resample.num_threads = a.options.num_threads;
  if (std::string why = a.resample.Check(); !why.empty()) return Fail("calibrate", why, kExitUsage);
  // The session first: a wrong path is named as such, not as a missing layout inside it.
  if (auto session = Session::Open(a.options.session); !session.ok()) return Fail("calibrate", session.status().message());
  if (a.layout_file.empty()) a.layout_file = a.options.session / "rig_layout.json";
  auto layout_json = ReadJsonFile(a.layout_file);
  if (!layout_json.ok()) return Fail("calibrate", layout_json.status().message() + " (give the rig's layout with --layout)");
  auto layout = RigLayout::FromJson(*layout_json);
  if (!layout.ok()) return Fail("calibrate", a.layout_file.string() + ": " + layout.status().message());
  Json intrinsics_report = Json::object();
  Image residual_plot;
  auto camera = CameraFor(a, *layout, &intrinsics_report, &residual_plot);
  if (!camera.ok()) return Fail("calibrate", camera.status().message());
  ProgressBar bar("calibrate", !a.no_progress);
  auto result = CalibrateSession(a.options, *layout, *camera, bar.AsCallback());
  if (!result.ok()) return Fail("calibrate", result.status().message());
  // calibration/ appears whole: a re-run swaps the new folder in only once every file is written.
  auto staging = StagingFolder::Begin(a.options.session / "calibration");
  if (!staging.ok()) return Fail("calibrate", staging.status().message());
  const fs::path out = staging->path();
  Json rig = result->RigJson();
  rig["provenance"] = MakeProvenance({{"session", a.options.session.string()}, {"pose_shots", a.options.pose_shots},
                                      {"camera_file", a.camera_file.string()}, {"layout", a.layout_file.string()}});
  Json report = result->ReportJson();
  report["intrinsics"] = intrinsics_report;
  if (Status st = WriteJsonFile(out / "rig.json", rig); !st.ok()) return Fail("calibrate", st.message());
  if (Status st = WriteJsonFile(out / "report.json", report); !st.ok()) return Fail("calibrate", st.message());
  // Plots a person reads at a glance: checkerboard residuals, and the flash directions seen from
  // the most head-on board (the top of the pyramid).
  if (!residual_plot.empty())
    if (Status st = WriteImage(out / "intrinsics_residuals.png", residual_plot, {.format = PixelFormat::kUint8Srgb}); !st.ok())
      return Fail("calibrate", st.message());
  const BoardPose* top = nullptr;
  for (const BoardPose& b : result->boards)
    if (b.found && (!top || std::abs(b.R(2, 2)) > std::abs(top->R(2, 2)))) top = &b;
  if (top) {
    std::vector<Eigen::Vector3d> dirs;
    for (const ShotCalibration& shot : result->shots)
      if (shot.light.ok) dirs.push_back(top->R.transpose() * (shot.light.light_m - top->t));
    const Image plot = HemispherePlot(dirs, 420, "flash directions, board " + std::to_string(top->id) + " frame");
    if (Status st = WriteImage(out / "lights.png", plot, {.format = PixelFormat::kUint8Srgb}); !st.ok())
      return Fail("calibrate", st.message());
  }
  if (Status st = staging->Publish(/*replace=*/true); !st.ok()) return Fail("calibrate", st.message());
  std::printf("calibrate: %s -> %s\n", result->Brief().c_str(), (staging->out() / "rig.json").string().c_str());
  for (const auto& r : result->rejected) std::printf("  rejected: %s\n", r.c_str());
  if (a.no_resample) return kExitOk;
  ProgressBar rbar("resample", !a.no_progress);
  auto slices = ResampleSession(a.resample, a.options.session, *layout, *result, rbar.AsCallback(), WriteBoardLightFiles);
  if (!slices.ok()) return Fail("calibrate", slices.status().message());
  std::printf("resample: %s -> %s\n", slices->Brief().c_str(),
              (a.options.session / "slices" / "index.json").string().c_str());
  std::map<std::string, int> skipped_by_reason;  // the full list is in index.json
  for (const auto& s : slices->skipped) ++skipped_by_reason[s.reason.substr(0, std::min(s.reason.find(" ("), s.reason.find(" by ")))];
  for (const auto& [reason, count] : skipped_by_reason) std::printf("  skipped %d: %s\n", count, reason.c_str());
  return kExitOk;
}

}  // namespace

Command CalibrateCommand() {
  auto args = std::make_shared<CalibrateArgs>();
  Command c;
  c.name = "calibrate";
  c.setup = [args](CLI::App& app) {
    CLI::App* sub = app.add_subcommand("calibrate", "Calibrate a session: board poses, balls, flash position and power per shot");
    sub->add_option("session", args->options.session, "Session folder")->required();
    sub->add_option("--camera", args->camera_file, "Intrinsics (camera.json from calibrate-camera); default: from the session's calib/ shots");
    sub->add_option("--layout", args->layout_file, "Rig layout (default SESSION/rig_layout.json)");
    sub->add_option("--pose-shots", args->options.pose_shots, "Shots searched for AprilTags")->capture_default_str();
    sub->add_option("--marked-corners", args->options.marked_corners,
                    "Hand-marked board corners (JSON, docs/formats.md) for boards whose tags are never decoded");
    sub->add_option("--threads", args->options.num_threads, "Threads (-1: all cores)")->capture_default_str();
    sub->add_option("--slice-size", args->resample.slice_size, "Texels per side of each resampled BTF slice")->capture_default_str();
    sub->add_flag("--no-resample", args->no_resample, "Calibrate only; do not write SESSION/slices/");
    sub->add_flag("--no-brdf-smoothing", args->no_brdf_smoothing,
                  "Do not rescale slices to the smoothed per-view average BRDF (absorbs flash-power error)");
    sub->add_option("--brdf-smoothing-deg", args->resample.brdf_smoothing_deg,
                    "Gaussian width over light directions of the BRDF smoothing")->capture_default_str();
    sub->add_flag("--no-progress", args->no_progress, "Do not draw progress bars");
  };
  c.run = [args]() { return Run(*args); };
  return c;
}

}  // namespace mesocap::app
