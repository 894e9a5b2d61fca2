// One RTI light file per board, SESSION/slices/board_BB.lp, listing its slices with their light
// directions in the patch frame (x right, y up the slice, z the normal: the .lp convention), so
// RTI tools and `mesocap fit-ptm --lp` read a board's slices as an RTI capture.
#pragma once

#include <cstdio>
#include <filesystem>

#include "calib/resample.h"
#include "core/status.h"

namespace mesocap::app {

Status WriteBoardLightFiles(const std::filesystem::path& slices_dir, const ResampleReport& slices);

inline std::filesystem::path BoardLightFile(const std::filesystem::path& slices_dir, int board) {
  char name[32];
  std::snprintf(name, sizeof name, "board_%02d.lp", board);
  return slices_dir / name;
}

}  // namespace mesocap::app
