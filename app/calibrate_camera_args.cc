#include "app/calibrate_camera_args.h"

#include <CLI/CLI.hpp>

namespace mesocap::app {

CLI::App* AddCalibrateCameraOptions(CLI::App& app, CalibrateCameraArgs* args) {
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
                  "CALIB_CB_ACCURACY, slow: about 20 s per 24 MP photo, which Ctrl-C waits for)")
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
  return sub;
}

}  // namespace mesocap::app
