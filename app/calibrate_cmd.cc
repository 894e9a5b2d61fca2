// mesocap calibrate SESSION: intrinsics (from the session's checkerboard shots or --camera),
// board poses, balls, flash position and power per shot -> SESSION/calibration/; then every
// lit board patch of every usable shot resampled into a BTF slice -> SESSION/slices/.
#include "app/calibrate_args.h"

#include <cstdio>
#include <memory>

#include "app/commands.h"
#include "app/session_stages.h"
#include "core/session.h"
#include "core/session_layout.h"
#include "core/session_lock.h"

namespace mesocap::app {
namespace {

namespace fs = std::filesystem;

}  // namespace

int RunCalibrate(CalibrateArgs& a) {
  CalibrateStageOptions stage;
  stage.calibrate = a.options;
  stage.camera_file = a.camera_file;
  stage.layout_file = a.layout_file;
  stage.progress = !a.no_progress;
  if (std::string why = a.options.Check(); !why.empty()) return Fail("calibrate", why, kExitUsage);
  a.resample.brdf_smoothing = !a.no_brdf_smoothing;
  a.resample.restore_chroma_detail = !a.no_chroma_detail;
  a.resample.num_threads = a.options.num_threads;
  if (std::string why = a.resample.Check(); !why.empty()) return Fail("calibrate", why, kExitUsage);
  if (auto session = Session::Open(a.options.session); !session.ok()) return Fail("calibrate", session.status());
  auto lock = SessionLock::Acquire(a.options.session, "calibrate");
  if (!lock.ok()) return Fail("calibrate", lock.status());
  auto calibrated = RunCalibrateStage(stage);
  if (!calibrated.ok()) return Fail("calibrate", calibrated.status());
  std::printf("calibrate: %s -> %s\n", calibrated->brief.c_str(), SessionLayout(a.options.session).calibration().rig().string().c_str());
  for (const auto& r : calibrated->warnings) std::printf("  rejected: %s\n", r.c_str());
  if (a.no_resample) return kExitOk;
  auto slices = RunResampleStage(a.options.session, a.layout_file, a.resample, !a.no_progress);
  if (!slices.ok()) return Fail("calibrate", slices.status());
  std::printf("resample: %s -> %s\n", slices->brief.c_str(), SessionLayout(a.options.session).slices().index().string().c_str());
  for (const auto& w : slices->warnings) std::printf("  %s\n", w.c_str());
  return kExitOk;
}
}  // namespace mesocap::app
