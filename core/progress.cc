#include "core/progress.h"

#include <unistd.h>

#include <cstdio>

namespace mesocap {

ProgressBar::ProgressBar(std::string label, bool enabled)
    : label_(std::move(label)), enabled_(enabled), tty_(::isatty(2)),
      start_(std::chrono::steady_clock::now()) {}

ProgressBar::~ProgressBar() {
  if (enabled_ && drawn_ && tty_) std::fputc('\n', stderr);
}

bool ProgressBar::Update(int done, int total, const std::string& what) {
  if (!enabled_ || total <= 0) return !CancelRequested();
  std::lock_guard<std::mutex> lock(mutex_);
  if (total != last_total_) last_total_ = total, highest_done_ = -1;  // a new phase
  if (done < highest_done_) return !CancelRequested();
  highest_done_ = done;
  const double frac = double(done) / total;
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double eta = done > 0 ? elapsed / done * (total - done) : 0.0;
  if (tty_) {
    const int width = 30, filled = int(frac * width);
    std::string bar(filled, '#');
    bar.resize(width, '.');
    std::fprintf(stderr, "\r%s [%s] %d/%d %5.1fs eta %5.1fs %-24.24s", label_.c_str(), bar.c_str(),
                 done, total, elapsed, eta, what.c_str());
    std::fflush(stderr);
    drawn_ = true;
  } else {
    const int decile = int(frac * 10);
    if (decile != last_decile_) {
      last_decile_ = decile;
      std::fprintf(stderr, "%s [%d/%d] %.1fs %s\n", label_.c_str(), done, total, elapsed, what.c_str());
    }
  }
  return !CancelRequested();  // Ctrl-C (core/cancel.h): the work stops at this report
}

ProgressFn ProgressBar::AsCallback() {
  return [this](int done, int total, const std::string& what) { return Update(done, total, what); };
}

}  // namespace mesocap
