// Long work reports "[i/N] name" through a callback; the CLI draws it as a progress bar.
// Returning false from the callback asks the work to stop early.
#pragma once

#include <chrono>
#include <functional>
#include <string>

namespace mesocap {

using ProgressFn = std::function<bool(int done, int total, const std::string& what)>;

inline bool ReportProgress(const ProgressFn& fn, int done, int total, const std::string& what) {
  return fn ? fn(done, total, what) : true;
}

// Draws a one-line bar on stderr (redrawn in place on a terminal, every 10% otherwise).
class ProgressBar {
 public:
  explicit ProgressBar(std::string label, bool enabled = true);
  ~ProgressBar();
  bool Update(int done, int total, const std::string& what);
  ProgressFn AsCallback();

 private:
  std::string label_;
  bool enabled_, tty_;
  int last_decile_ = -1;
  bool drawn_ = false;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace mesocap
