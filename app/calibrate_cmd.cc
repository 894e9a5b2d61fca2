// mesocap calibrate SESSION: intrinsics (from the session's checkerboard shots or --camera),
// board poses, balls, flash position and power per shot -> SESSION/calibration/; then every
// lit board patch of every usable shot resampled into a BTF slice -> SESSION/slices/.
#include <cstdio>
#include <memory>

#include "app/commands.h"
#include "app/session_stages.h"

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

int Run(CalibrateArgs& a) {
  CalibrateStageOptions stage;
  stage.calibrate = a.options;
  stage.camera_file = a.camera_file;
  stage.layout_file = a.layout_file;
  stage.progress = !a.no_progress;
  if (std::string why = a.options.Check(); !why.empty()) return Fail("calibrate", why, kExitUsage);
  a.resample.brdf_smoothing = !a.no_brdf_smoothing;
  a.resample.num_threads = a.options.num_threads;
  if (std::string why = a.resample.Check(); !why.empty()) return Fail("calibrate", why, kExitUsage);
  auto calibrated = RunCalibrateStage(stage);
  if (!calibrated.ok()) return Fail("calibrate", calibrated.status().message());
  std::printf("calibrate: %s -> %s\n", calibrated->brief.c_str(), (a.options.session / "calibration" / "rig.json").string().c_str());
  for (const auto& r : calibrated->warnings) std::printf("  rejected: %s\n", r.c_str());
  if (a.no_resample) return kExitOk;
  auto slices = RunResampleStage(a.options.session, a.layout_file, a.resample, !a.no_progress);
  if (!slices.ok()) return Fail("calibrate", slices.status().message());
  std::printf("resample: %s -> %s\n", slices->brief.c_str(), (a.options.session / "slices" / "index.json").string().c_str());
  for (const auto& w : slices->warnings) std::printf("  %s\n", w.c_str());
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
