#include "app/calibrate_args.h"

#include <CLI/CLI.hpp>

#include "core/session_layout.h"

namespace mesocap::app {

CLI::App* AddCalibrateOptions(CLI::App& app, CalibrateArgs* args) {
  const SessionLayout S = HelpLayout();
  CLI::App* sub = app.add_subcommand("calibrate", "Calibrate a session: board poses, balls, flash position and power per shot");
  sub->add_option("session", args->options.session, "Session folder")->required();
  sub->add_option("--camera", args->camera_file, "Intrinsics (camera.json from calibrate-camera); default: from the session's " + FolderName(S.calib()) + " shots");
  sub->add_option("--layout", args->layout_file, "Rig layout (default " + S.rig_layout().string() + ")");
  sub->add_option("--pose-shots", args->options.pose_shots, "Shots searched for AprilTags")->capture_default_str();
  sub->add_option("--marked-corners", args->options.marked_corners,
                  "Hand-marked board corners (JSON, docs/formats.md) for boards whose tags are never decoded");
  sub->add_option("--threads", args->options.num_threads, "Threads (-1: all cores)")->capture_default_str();
  sub->add_option("--slice-size", args->resample.slice_size, "Texels per side of each resampled BTF slice")->capture_default_str();
  sub->add_flag("--no-resample", args->no_resample, "Calibrate only; do not write " + S.slices().root.string() + "/");
  sub->add_flag("--no-brdf-smoothing", args->no_brdf_smoothing,
                "Do not rescale slices to the smoothed per-view average BRDF (absorbs flash-power error)");
  sub->add_flag("--no-chroma-detail", args->no_chroma_detail,
                "Resample JPEG shots with their colour as stored at half resolution, instead of restoring its detail from the brightness");
  sub->add_option("--brdf-smoothing-deg", args->resample.brdf_smoothing_deg,
                  "Gaussian width over light directions of the BRDF smoothing")->capture_default_str();
  sub->add_flag("--no-progress", args->no_progress, "Do not draw progress bars");
  return sub;
}

}  // namespace mesocap::app
