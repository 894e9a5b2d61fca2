// Residual plot for a checkerboard calibration (an image operation: result in, image out, no
// file I/O). Left panel: the image frame with every used corner's reprojection residual drawn
// as a magnified vector, one colour per image. Right panel: all residuals as a scatter around
// (0, 0) with circles at 1x and 3x the RMS. Values are linear RGB in [0, 1].
#pragma once

#include "calib/intrinsics.h"
#include "core/image.h"

namespace mesocap {

struct ResidualPlotOptions {
  int width_px = 1600;        // whole plot; the height follows the camera's aspect ratio
  double vector_scale = 0;    // residual magnification in the left panel; 0: automatic
                              // (the 99th percentile residual is drawn 4% of the panel wide)
  std::string Check() const;  // empty when valid
};

Image PlotIntrinsicsResiduals(const IntrinsicsResult& result, const ResidualPlotOptions& options = {});

}  // namespace mesocap
