// Logging through spdlog, to stderr only (stdout is for a command's own result lines).
#pragma once

#include <spdlog/spdlog.h>

namespace mesocap {

// verbosity: 0 = warnings and errors, 1 = info (default), 2 = debug.
void InitLogging(int verbosity);

}  // namespace mesocap
