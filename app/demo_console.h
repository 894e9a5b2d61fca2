// The demo's capture console: `mesocap console` on the virtual camera, the demo as the operator
// following the page's suggestions through its API, and screenshots of the page (headless
// Chromium) at three moments, for the demo's report. It runs on a thread of its own, alongside
// the demo's other stages (its own session, its own child processes), to use the cores they leave.
#pragma once

#include <filesystem>
#include <future>
#include <string>
#include <utility>
#include <vector>

#include "core/status.h"
#include "export/report.h"

namespace mesocap::app {

struct ConsoleRecording {
  std::filesystem::path session;
  std::vector<double> coverage_percents;  // after each flash shot
  std::vector<std::pair<std::string, std::string>> pictures;  // file (in the demo's folder), caption
  double finish_seconds = 0;  // from finish to `mesocap process` done
  double seconds = 0;         // the whole recording
};

// Starts the recording into `out` (console_session/, console.log, the screenshots).
std::future<StatusOr<ConsoleRecording>> StartConsoleRecording(const std::filesystem::path& out);
void AddConsoleToReport(const ConsoleRecording& recording, Report* report);

}  // namespace mesocap::app
