// The rig as calibrated, drawn in the top board's frame (metres, z along its normal): a plan view
// (x, y) and a side view (distance from the top board's centre across the table, height), with
// every board's patch, the balls, the camera and each calibrated flash position. Shows where the
// flash has been around the target, and where it has not.
#pragma once

#include "calib/calibrate.h"
#include "core/image.h"
#include "core/rig_layout.h"

namespace mesocap::app {

// The posed board whose normal is closest to the camera's axis (the top of the pyramid), or null.
const BoardPose* TopBoardPose(const CalibrationResult& result);

// An empty image when no board was posed.
Image FlashPositionsPlot(const CalibrationResult& result, const RigLayout& layout, int panel_size = 360);

}  // namespace mesocap::app
