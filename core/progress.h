// Long work reports "[i/N] name" through a callback; the CLI draws it as a progress bar.
// Returning false from the callback asks the work to stop early.
#pragma once

#include <chrono>
#include <functional>
#include <mutex>
#include <string>

#include "core/cancel.h"

namespace mesocap {

using ProgressFn = std::function<bool(int done, int total, const std::string& what)>;

// Wall seconds since `start` (steady clock): every stage's timing figures.
inline double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// False when the work should stop: the callback said so, or the user pressed Ctrl-C (core/cancel.h).
inline bool ReportProgress(const ProgressFn& fn, int done, int total, const std::string& what) {
  if (CancelRequested()) return false;
  return fn ? fn(done, total, what) : true;
}

// Draws a one-line bar on stderr (redrawn in place on a terminal, every 10% otherwise). Update
// may be called from parallel workers: calls are serialised, and a report older than one already
// drawn (workers finish out of order) does not move the bar back.
class ProgressBar {
 public:
  explicit ProgressBar(std::string label, bool enabled = true);
  ~ProgressBar();
  bool Update(int done, int total, const std::string& what);
  ProgressFn AsCallback();

 private:
  std::mutex mutex_;
  std::string label_;
  bool enabled_, tty_;
  int highest_done_ = -1, last_total_ = 0;
  int last_decile_ = -1;
  bool drawn_ = false;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace mesocap
