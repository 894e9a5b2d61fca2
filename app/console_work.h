// The capture console's work behind its page (`mesocap console`, docs/console.md), on three
// threads of its own: the camera's (capture runs in enter mode, each shot waiting for the page's
// button; the camera is driven only from this thread), the analysis's (each new shot's flash and
// usability, the coverage and the next suggestion, its thumbnail: guidance never delays the
// camera), and, at finish, `mesocap process` as a child working under the console's lock, its
// progress streamed to the page. Every change goes through the ConsoleState.
#pragma once

#include <sys/types.h>

#include <condition_variable>
#include <deque>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "app/capture_guide.h"
#include "app/console_state.h"
#include "capture/camera.h"
#include "capture/tethered_capture.h"

namespace mesocap::app {

struct ConsoleWorkOptions {
  std::filesystem::path session;  // exists (created or resumed), its lock held by the caller
  CaptureMode mode = CaptureMode::kEnter;
  std::vector<std::string> settings;
  bool guide = true;  // off: shots and thumbnails only (no flash, coverage or suggestions)
  bool follow_guide = false;
  CaptureGuideOptions guidance;
  std::vector<std::string> process_args;
  bool review = false;  // no camera: the page shows the session as it is
};

// The state a page starts from: every journaled shot (rejected ones marked), the coverage and the
// report when the session has them.
Json InitialConsoleState(const std::filesystem::path& session, bool review);

class ConsoleWork {
 public:
  // `camera` is null in review. Starts the threads; shots already in the session are analysed
  // again (a resumed console shows them as before).
  ConsoleWork(ConsoleWorkOptions options, std::unique_ptr<Camera> camera, ConsoleState* state);
  ~ConsoleWork();

  // The page's buttons: empty when queued, else why not.
  std::string RequestShot(const std::string& kind);  // "shot" or "calib"
  std::string RequestUndo();
  std::string RequestFinish();

  bool finished() const;  // finish is done (whatever its outcome)
  // Stops capture after the current shot, ends the threads.
  void Stop();

 private:
  struct Job {
    std::string what;  // "shot", "calib", "undo"
    std::string file;
  };
  void CaptureLoop();
  bool WaitForShot(const std::string& kind);  // ReadyFn: true to take the next shot of `kind`
  void TakeUndos(std::unique_lock<std::mutex>& hold);  // runs the undos at the queue's front
  void UndoShot(const std::string& file);
  void ReconcileWithJournal();
  void AfterShot(const CapturedShot& shot);
  void AnalysisLoop();
  void Analyse(const Job& job);
  void StartGuideIfNeeded();
  void RecordGuidance(const std::string& file, const ShotGuidance& g, const std::string& kind);
  void WriteThumbnail(const std::string& file);
  void Finish();
  void WaitForAnalysis();

  ConsoleWorkOptions options_;
  std::unique_ptr<Camera> camera_;
  ConsoleState* state_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  inline static const std::string kUndo = "undo ";
  std::deque<std::string> commands_;  // "shot", "calib", "undo FILE", "finish"
  std::deque<Job> jobs_;
  bool analysing_ = false, stopping_ = false, finishing_ = false, finished_ = false;
  bool reconcile_ = false;  // the page is compared with the journal at the next chance
  pid_t child_ = 0;         // finish's `mesocap process`, while it runs
  std::unique_ptr<CaptureGuide> guide_;
  size_t guide_failed_at_calib_shots_ = size_t(-1);
  std::thread camera_thread_, analysis_thread_;
};

}  // namespace mesocap::app
