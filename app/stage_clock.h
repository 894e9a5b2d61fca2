// Wall time per stage of a multi-stage command (the demo), for its report: a person sees where
// the time went, and the total is checked against the demo's one-minute budget.
#pragma once

#include <chrono>
#include <string>
#include <utility>
#include <vector>

namespace mesocap::app {

class StageClock {
 public:
  StageClock() : start_(Clock::now()), stage_start_(start_) {}

  // Ends the running stage, if any, and starts `name`.
  void Start(const std::string& name) {
    Stop();
    running_ = name;
  }

  void Stop() {
    const auto now = Clock::now();
    if (!running_.empty()) stages_.push_back({running_, std::chrono::duration<double>(now - stage_start_).count()});
    running_.clear();
    stage_start_ = now;
  }

  // A stage timed elsewhere (e.g. by `process`); ends the running one.
  void Add(const std::string& name, double seconds) {
    Stop();
    stages_.push_back({name, seconds});
  }

  const std::vector<std::pair<std::string, double>>& stages() const { return stages_; }
  double TotalSeconds() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }

 private:
  using Clock = std::chrono::steady_clock;
  Clock::time_point start_, stage_start_;
  std::string running_;
  std::vector<std::pair<std::string, double>> stages_;
};

}  // namespace mesocap::app
