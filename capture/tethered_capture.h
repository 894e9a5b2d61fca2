// `mesocap capture`: tethered capture into a session folder through the Camera interface.
// Each file is downloaded to a temp name beside its final name, checked (size, JPEG end marker),
// fsynced and renamed into shots/ (or calib/), and only then appended to the journal with the
// time, the camera settings and the EXIF read back from the file. A crash at any moment leaves
// every completed shot intact; --resume continues the numbering without overwriting anything
// and journals complete files a crash left unjournaled (flag "recovered").
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "capture/camera.h"
#include "core/json.h"
#include "core/progress.h"
#include "core/status.h"

namespace mesocap {

enum class CaptureMode {
  kInterval,  // `shots` pictures, one every `interval_s` seconds
  kEnter,     // one picture each time the photographer presses Enter
  kRemote,    // the photographer fires the camera (remote release); each new file is downloaded
};
std::string CaptureModeToString(CaptureMode mode);                  // "interval", "enter", "remote"
bool StringToCaptureMode(const std::string& s, CaptureMode* mode);  // false when unknown

// Busy and I/O errors are retried with exponential backoff.
struct RetryOptions {
  int max_attempts = 6;            // per operation, the first try included
  double initial_backoff_s = 0.25; // pause after the first failure; doubles after each one
  double max_backoff_s = 4.0;
};

struct CaptureOptions {
  std::filesystem::path out;          // session folder: new (missing or empty), or existing with resume
  int shots = 1;                      // pictures this run; remote mode: 0 = until cancelled
  double interval_s = 0;              // interval mode: seconds from one shot's start to the next
  std::vector<std::string> settings;  // "key=value" camera settings, applied in order first
  bool calibration = false;           // checkerboard shots: kind "calib", into calib/
  bool resume = false;                // add to an existing session, numbering after its last shot
  CaptureMode mode = CaptureMode::kInterval;
  double remote_idle_timeout_s = 0;   // remote mode: stop after this long without a file (0: never)
  bool delete_from_camera = false;    // delete each file from the card once it is safely in the
                                      // session (keeps a RAM-buffer capture target from filling)
  RetryOptions retry;
  bool locked_by_caller = false;      // the caller holds the session's lock (the console, which
                                      // captures and processes under one lock for its whole run)

  std::string Check() const;  // empty when valid, else a message for the user
  Json ToJson() const;
};

struct CapturedShot {
  int index = 0;
  std::string kind;     // "shot" or "calib"
  std::string file;     // relative to the session root
  std::string on_card;  // where the camera stored it
  int64_t bytes = 0;
  double camera_s = 0;    // in the camera: capture (or event wait) + download
  double overhead_s = 0;  // mesocap's own work: verify, fsync, rename, EXIF, journal
  int retries = 0;
  std::vector<std::string> flags;
  Json ToJson() const;
};

struct CaptureReport {
  std::filesystem::path out;
  CameraInfo camera;
  Json settings = Json::object();  // the camera settings recorded with every shot
  int first_index = 0;             // index of this run's first shot (after a resume: > 1)
  int shots_captured = 0;          // this run
  int recovered = 0;               // complete files a crash left unjournaled, journaled on resume
  int removed_partial_files = 0;   // temp files of interrupted downloads, deleted on resume
  int retries = 0;                 // busy / I/O retries, all shots
  int flash_not_fired = 0;
  std::vector<CapturedShot> shots;
  std::vector<std::string> warnings;
  std::string stop_reason = "done";  // done, cancelled, idle_timeout, camera_gone, camera_not_responding,
                                     // card_full, disk_full, error
  std::string error;                 // why the run ended early; empty when it finished
  double total_s = 0;
  double mean_camera_s = 0, mean_overhead_s = 0, max_overhead_s = 0;

  bool ok() const { return error.empty(); }
  Json ToJson() const;  // written as SESSION/capture_report.json
  std::string Brief() const;
};

// Called in enter mode before shot `number` (1-based) of `total`; blocks until the photographer
// is ready and returns false to stop.
using ReadyFn = std::function<bool(int number, int total)>;

// Called after each shot is safely in the session and journaled (capture guidance looks at it);
// the next shot is taken when it returns.
using AfterShotFn = std::function<void(const CapturedShot& shot)>;

// The manifest of a new session captured from `camera` with `options` (source, camera, provenance).
Json CaptureManifest(const CameraInfo& camera, const CaptureOptions& options);

// Checks every "key=value" of `settings` against the camera without changing anything; a wrong
// key or value is kBadSetting and the message lists the valid keys or values.
CameraStatus ValidateSettings(Camera& camera, const std::vector<std::string>& settings);

// Applies the settings, then captures into the session. Returns an error Status when nothing
// could start (bad option, session cannot be created or opened, a setting rejected). Once the
// session exists, the report always comes back, with `error` and `stop_reason` set when the run
// ended early (camera unplugged, card or disk full, retries exhausted): the shots taken so far
// are intact and journaled. Progress: "[i/N] shots/shot_0007.jpg f/8 1/125 ISO 200"; returning
// false cancels after the current shot. The report is also written to SESSION/capture_report.json.
StatusOr<CaptureReport> RunCapture(Camera& camera, const CaptureOptions& options, const ProgressFn& progress = nullptr,
                                   const ReadyFn& ready = nullptr, const AfterShotFn& after_shot = nullptr);

}  // namespace mesocap
