// The demo's synthesis section: the session's reconstructed BTF enlarged by the roller and by
// graphcut quilting, and the top board's PTM by block synthesis, side by side under three lights,
// with their seam figures and timings.
#pragma once

#include <filesystem>

#include "app/stage_clock.h"
#include "core/status.h"
#include "export/report.h"

namespace mesocap::app {

// `session` after `process` (btf/, ptm/); pictures go into `out`. Each method is one clock stage.
Status AddSynthesisToDemo(const std::filesystem::path& out, const std::filesystem::path& session, int top_board,
                          StageClock* clock, Report* report);

}  // namespace mesocap::app
