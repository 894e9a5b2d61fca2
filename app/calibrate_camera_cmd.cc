// mesocap calibrate-camera: camera intrinsics from any folder of checkerboard photos.
// Writes camera.json (CameraModel::ToJson keys width, height, K, dist, plus "report", the
// per-image solver inputs under "images", and "provenance") and a residual plot PNG beside it.
#include "app/calibrate_camera_args.h"

#include <cstdio>
#include <memory>

#include "app/commands.h"
#include "core/atomic_file.h"
#include "calib/intrinsics.h"
#include "calib/intrinsics_plot.h"
#include "core/image_io.h"
#include "core/progress.h"
#include "core/provenance.h"

namespace mesocap::app {
namespace {

// "9x6" -> cols 9, rows 6; false unless the whole text is two positive integers around an 'x'.
bool ParseBoard(const std::string& text, int* cols, int* rows) {
  int c = 0, r = 0, used = 0;
  if (std::sscanf(text.c_str(), "%dx%d%n", &c, &r, &used) != 2 || used != int(text.size())) return false;
  if (c <= 0 || r <= 0) return false;
  *cols = c;
  *rows = r;
  return true;
}

}  // namespace

int RunCalibrateCamera(CalibrateCameraArgs& a) {
  const char* verb = "calibrate-camera";
  IntrinsicsOptions& o = a.options;
  if (!ParseBoard(a.board, &o.cols, &o.rows))
    return Fail(verb, "--board must be COLSxROWS inner corners, e.g. 9x6, not '" + a.board + "'", kExitUsage);
  if (!StringToRobustLoss(a.loss, &o.loss))
    return Fail(verb, "--loss must be huber, cauchy or none, not '" + a.loss + "'", kExitUsage);
  if (!StringToCornerRefinement(a.refinement, &o.refinement))
    return Fail(verb, "--refinement must be subpix or sb-accuracy, not '" + a.refinement + "'", kExitUsage);
  if (std::string why = o.Check(); !why.empty()) return Fail(verb, why, kExitUsage);
  if (a.out.empty() || a.out.extension() != ".json") return Fail(verb, "--out must name a .json file", kExitUsage);
  if (a.plot.empty()) a.plot = a.out.parent_path() / (a.out.stem().string() + "_residuals.png");

  auto files = ListCalibrationImages(a.images_dir);
  if (!files.ok()) return Fail(verb, files.status().message(), kExitUsage);
  if (files->empty()) return Fail(verb, a.images_dir.string() + ": no image files (jpg, png, tif, exr, raw)");

  ProgressBar bar(verb, !a.no_progress);
  auto result = CalibrateIntrinsics(*files, o, bar.AsCallback());
  if (!result.ok()) return Fail(verb, result.status());

  Json j = result->camera.ToJson();
  const Json full = result->ToJson();
  j["report"] = full.at("report");
  j["images"] = full.at("images");
  Json resolved = o.ToJson();
  resolved["images_dir"] = a.images_dir.string();
  j["provenance"] = MakeProvenance(resolved);
  std::error_code ec;
  if (!a.out.parent_path().empty()) std::filesystem::create_directories(a.out.parent_path(), ec);
  OutputFileSet outputs;  // camera.json and its plot appear together or not at all
  if (!a.no_plot) {
    const Image plot = PlotIntrinsicsResiduals(*result);
    ImageWriteOptions w;
    w.format = PixelFormat::kUint8Srgb;
    if (Status st = outputs.Stage(a.plot, [&](const std::filesystem::path& temp) { return WriteImage(temp, plot, w); });
        !st.ok())
      return Fail(verb, st);
  }
  if (Status st = outputs.Stage(a.out, [&](const std::filesystem::path& temp) { return WriteJsonFile(temp, j); });
      !st.ok())
    return Fail(verb, st);
  if (Status st = outputs.Commit(); !st.ok()) return Fail(verb, st);
  std::string written = a.out.string();
  if (!a.no_plot) written += ", " + a.plot.string();
  std::printf("%s\n-> %s\n", result->Brief().c_str(), written.c_str());
  return kExitOk;  // rejected images are listed; the exit code stays 0
}
}  // namespace mesocap::app
