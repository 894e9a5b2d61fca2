// The demo's capture console: `mesocap console` on the virtual camera, the demo as the operator
// following the page's suggestions through its API, and screenshots of the page (headless
// Chromium) at three moments, for the demo's report.
#pragma once

#include <filesystem>

#include "core/status.h"
#include "export/report.h"

namespace mesocap::app {

Status AddConsoleToDemo(const std::filesystem::path& out, Report* report);

}  // namespace mesocap::app
