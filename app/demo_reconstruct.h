// The demo's reconstruction stages, run on the session the demo calibrated: a PTM of the top
// board's slices, the statistical BTF from all boards' slices scored against the true BTF, and
// the paper's validation (`mesocap evaluate`) at a small size.
#pragma once

#include <filesystem>

#include <Eigen/Core>

#include "app/stage_clock.h"
#include "capture/rig_material.h"
#include "core/status.h"
#include "export/report.h"

namespace mesocap::app {

struct DemoReconstructionInputs {
  std::filesystem::path out;      // the demo folder
  std::filesystem::path session;  // with slices/index.json and slices/board_00.lp
  const Material* material = nullptr;
  int top_board = 0;
  Eigen::Vector2d top_offset_m{0, 0};  // where the top patch sits in the material
  double patch_m = 0.064;
  bool progress = true;
  StageClock* clock = nullptr;  // each stage starts its entry
};

// Adds its headings, tables and pictures to `report`; prints one line per stage.
Status AddReconstructionToDemo(const DemoReconstructionInputs& in, Report* report);

}  // namespace mesocap::app
