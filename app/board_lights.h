// One RTI light file per board, SESSION/slices/board_BB.lp, listing its slices with their light
// directions in the patch frame (x right, y up the slice, z the normal: the .lp convention), so
// RTI tools and `mesocap fit-ptm --lp` read a board's slices as an RTI capture.
#pragma once

#include <filesystem>

#include "calib/resample.h"
#include "core/status.h"

namespace mesocap::app {

Status WriteBoardLightFiles(const std::filesystem::path& slices_dir, const ResampleReport& slices);

}  // namespace mesocap::app
