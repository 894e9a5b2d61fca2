// mesocap calibrate-camera: camera intrinsics from any folder of checkerboard photos.
// Writes camera.json (CameraModel::ToJson keys width, height, K, dist, plus "report", the
// per-image solver inputs under "images", and "provenance") and a residual plot PNG beside it.
//
// To wire in: declare `Command CalibrateCameraCommand();` in app/commands.h, add it to
// AllCommands() in app/commands.cc, and add calibrate_camera_cmd.cc and mesocap_calib to the
// mesocap target in app/CMakeLists.txt.
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

struct CalibrateCameraArgs {
  IntrinsicsOptions options;
  std::filesystem::path images_dir;
  std::string board;  // "COLSxROWS", inner corners
  std::filesystem::path out;
  std::filesystem::path plot;  // empty: beside --out, named <stem>_residuals.png
  std::string loss = "huber";
  std::string refinement = "subpix";
  bool no_plot = false;
  bool no_progress = false;
};

// "9x6" -> cols 9, rows 6; false unless the whole text is two positive integers around an 'x'.
bool ParseBoard(const std::string& text, int* cols, int* rows) {
  int c = 0, r = 0, used = 0;
  if (std::sscanf(text.c_str(), "%dx%d%n", &c, &r, &used) != 2 || used != int(text.size())) return false;
  if (c <= 0 || r <= 0) return false;
  *cols = c;
  *rows = r;
  return true;
}

int Run(CalibrateCameraArgs& a) {
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
  if (!result.ok()) {
    const bool cancelled = result.status().message() == "cancelled";
    return Fail(verb, result.status().message(), cancelled ? kExitCancelled : kExitFailure);
  }

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
      return Fail(verb, st.message());
  }
  if (Status st = outputs.Stage(a.out, [&](const std::filesystem::path& temp) { return WriteJsonFile(temp, j); });
      !st.ok())
    return Fail(verb, st.message());
  if (Status st = outputs.Commit(); !st.ok()) return Fail(verb, st.message());
  std::string written = a.out.string();
  if (!a.no_plot) written += ", " + a.plot.string();
  std::printf("%s\n-> %s\n", result->Brief().c_str(), written.c_str());
  return kExitOk;  // rejected images are listed; the exit code stays 0
}

}  // namespace

Command CalibrateCameraCommand() {
  auto args = std::make_shared<CalibrateCameraArgs>();
  Command c;
  c.name = "calibrate-camera";
  c.setup = [args](CLI::App& app) {
    CLI::App* sub = app.add_subcommand("calibrate-camera",
                                       "Camera intrinsics (K and 5 distortion coefficients) from a folder of "
                                       "checkerboard photos");
    IntrinsicsOptions& o = args->options;
    sub->add_option("--images", args->images_dir, "Folder of checkerboard photos (not searched recursively)")
        ->required();
    sub->add_option("--board", args->board, "Inner corners COLSxROWS, e.g. 9x6 (OpenCV's patternSize)")->required();
    sub->add_option("--square", o.square_m, "Side of one square, metres")->required();
    sub->add_option("--out", args->out, "Output camera.json")->required();
    sub->add_option("--plot", args->plot, "Residual plot PNG (default: beside --out, <name>_residuals.png)");
    sub->add_flag("--no-plot", args->no_plot, "Do not write the residual plot");
    sub->add_option("--refinement", args->refinement,
                    "Corner refinement: subpix (fast, default) or sb-accuracy (findChessboardCornersSB "
                    "CALIB_CB_ACCURACY, slow)")
        ->capture_default_str();
    sub->add_option("--loss", args->loss, "Robust loss: huber, cauchy or none")->capture_default_str();
    sub->add_option("--loss-scale", o.loss_scale_px, "Robust loss scale, pixels")->capture_default_str();
    sub->add_option("--outlier-factor", o.outlier_rms_factor,
                    "Reject an image whose RMS exceeds this many times the median image RMS")
        ->capture_default_str();
    sub->add_option("--outlier-floor", o.outlier_min_rms_px, "...and exceeds this RMS, pixels")
        ->capture_default_str();
    sub->add_option("--max-edge-rise", o.max_edge_rise_px,
                    "Reject a board whose edges rise over more pixels than this (blur); 0: off")
        ->capture_default_str();
    sub->add_option("--blur-factor", o.blur_median_factor,
                    "...and more than this many times the median of the images")
        ->capture_default_str();
    sub->add_option("--min-images", o.min_images, "Fewest usable images to calibrate from")->capture_default_str();
    sub->add_option("--threads", o.num_threads, "Threads (-1: all cores)")->capture_default_str();
    sub->add_flag("--no-progress", args->no_progress, "Do not draw a progress bar");
  };
  c.run = [args]() { return Run(*args); };
  return c;
}

}  // namespace mesocap::app
