#include "app/console_work.h"

#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <chrono>
#include <fstream>
#include <set>
#include <tuple>

#include "app/guided_capture.h"
#include "app/rig_plot.h"
#include "core/image_io.h"
#include "core/provenance.h"
#include "core/session.h"
#include "core/session_layout.h"
#include "export/previews.h"

extern char** environ;

namespace mesocap::app {
namespace fs = std::filesystem;

namespace {

constexpr int kThumbnailWidth = 320, kViewWidth = 1600;
constexpr size_t kProcessLinesKept = 400;

std::string FileUrl(const SessionLayout& layout, const fs::path& path) { return "/files/" + layout.Relative(path); }

// The shot's own file where a browser shows it as it is (until its view is made), else null.
Json BrowserImage(const std::string& file) {
  std::string ext = fs::path(file).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext == ".jpg" || ext == ".jpeg" || ext == ".png" ? Json("/files/" + file) : Json();
}

Json ShotEntry(const ShotRecord& r) {
  // What the shot's own reading found against it; why_not adds the calibration's verdict.
  Json problems = Json::array();
  const bool not_fired = std::find(r.flags.begin(), r.flags.end(), "flash_not_fired") != r.flags.end();
  if (not_fired) problems.push_back("the flash did not fire (the photo's EXIF says so)");
  return {{"file", r.file}, {"kind", r.kind}, {"index", r.index}, {"time_utc", r.time_utc},
          {"image", BrowserImage(r.file)}, {"thumbnail", BrowserImage(r.file)}, {"flags", r.flags},
          {"usable", not_fired ? Json(false) : Json()}, {"why_not", problems}, {"read_problems", problems},
          {"warnings", Json::array()}, {"flash", nullptr}, {"rejected", false}, {"analysed", false}};
}

Json CoverageSummaryJson(const CoverageAssessment& a, const std::string& plot_url) {
  Json boards = Json::array();
  for (const BoardCoverage& b : a.report.boards)
    boards.push_back({{"board", b.board}, {"lights", b.lights}, {"covered", b.targets_covered}, {"reachable", b.targets_reachable}});
  return {{"covered", a.report.covered}, {"reachable", a.report.reachable}, {"percent", 100.0 * a.report.score()},
          {"boards", boards}, {"plot", plot_url}};
}

Json SuggestionsJson(const CoverageAssessment& a) {
  Json next = Json::array();
  for (const FlashSuggestion& s : a.report.next)
    next.push_back({{"words", s.words}, {"targets_gained", s.targets_gained}, {"elevation_deg", s.elevation_deg},
                    {"azimuth_deg", s.azimuth_deg}, {"position_cam_m", ToJson(s.position_cam)}});
  return next;
}

// Review: each flash shot's verdict as the session's calibration gave it (unknown without one).
void MarkCalibrationVerdicts(const SessionLayout& layout, Json* state) {
  std::map<std::string, Json> light;  // file -> calibration's reading of its flash
  if (auto report = ReadJsonFile(layout.calibration().report()); report.ok() && report->is_object())
    for (const Json& shot : report->value("shots", Json::array()))
      if (shot.is_object() && shot.contains("file") && shot["file"].is_string())
        light[shot["file"].get<std::string>()] = shot.value("light", Json::object());
  for (Json& shot : (*state)["shots"]) {
    shot["analysed"] = true;
    const auto it = light.find(shot["file"].get<std::string>());
    if (shot["kind"] != "shot" || it == light.end() || !it->second.is_object()) continue;
    const Json ok = it->second.value("ok", Json()), flag = it->second.value("flag", Json());
    const bool found = ok.is_boolean() && ok.get<bool>();  // a hand-edited report is not trusted
    shot["usable"] = found && shot["read_problems"].empty();
    if (!found) shot["why_not"].push_back("no flash position: " + (flag.is_string() ? flag.get<std::string>() : "not found"));
  }
}

}  // namespace

Json InitialConsoleState(const fs::path& session, bool review) {
  const SessionLayout layout(session);
  Json state = {{"format", "mesocap-console-state"}, {"format_version", 1},
                {"session", fs::absolute(session).lexically_normal().string()},
                {"mode", review ? "review" : "capture"},
                {"capture", {{"state", review ? "review" : "starting"}, {"kind", "shot"}, {"error", ""}}},
                {"shots", Json::array()}, {"coverage", nullptr}, {"next", Json::array()}, {"notes", Json::array()},
                {"process", {{"state", "idle"}, {"lines", Json::array()}, {"report", nullptr}, {"log", nullptr}}}};
  if (auto opened = Session::Open(session); opened.ok()) {
    for (const ShotRecord& r : opened->shots()) {
      Json entry = ShotEntry(r);
      entry["rejected"] = opened->IsRejected(r.file);
      if (fs::exists(layout.console_thumbnail(r.file))) entry["thumbnail"] = FileUrl(layout, layout.console_thumbnail(r.file));
      if (fs::exists(layout.console_view(r.file))) entry["image"] = FileUrl(layout, layout.console_view(r.file));
      state["shots"].push_back(entry);
    }
  }
  if (review) MarkCalibrationVerdicts(layout, &state);
  if (auto coverage = ReadJsonFile(layout.coverage().assessment()); review && coverage.ok() && coverage->is_object()) {
    const auto count = [&](const char* key) {
      const Json v = coverage->value(key, Json());
      return v.is_number_integer() ? std::max<int64_t>(0, v.get<int64_t>()) : 0;
    };
    const int64_t covered = count("covered"), reachable = count("reachable");
    state["coverage"] = {{"covered", covered}, {"reachable", reachable},
                         {"percent", reachable ? 100.0 * double(covered) / double(reachable) : 100.0}, {"boards", Json::array()},
                         {"plot", FileUrl(layout, layout.coverage().plot())}};
  }
  if (fs::exists(layout.report_html())) state["process"]["report"] = FileUrl(layout, layout.report_html());
  return state;
}

ConsoleWork::ConsoleWork(ConsoleWorkOptions options, std::unique_ptr<Camera> camera, ConsoleState* state)
    : options_(std::move(options)), camera_(std::move(camera)), state_(state) {
  if (options_.review) return;
  // A resumed session's shots are read again, in order, as if they had just come.
  const Json resumed = state_->Snapshot();
  for (const Json& shot : resumed["shots"])
    if (!shot["rejected"].get<bool>()) jobs_.push_back({shot["kind"].get<std::string>(), shot["file"].get<std::string>()});
  analysis_thread_ = std::thread([this] { AnalysisLoop(); });
  camera_thread_ = std::thread([this] { CaptureLoop(); });
}

ConsoleWork::~ConsoleWork() { Stop(); }

std::string ConsoleWork::RequestShot(const std::string& kind) {
  if (options_.review) return "review: there is no camera";
  if (kind == "shot" && options_.mode == CaptureMode::kRemote) return "the photographer fires the camera (remote mode)";
  std::lock_guard<std::mutex> hold(mutex_);
  if (finishing_) return "the session is finished";
  const Json capture = state_->Snapshot()["capture"];
  if (capture["state"] == "error") return "the camera stopped: " + capture["error"].get<std::string>();
  commands_.push_back(kind);
  wake_.notify_all();
  return "";
}

std::string ConsoleWork::RequestUndo() {
  if (options_.review) return "review: nothing is changed";
  std::lock_guard<std::mutex> hold(mutex_);
  if (finishing_) return "the session is finished";
  // The last flash shot the operator sees that no undo asks for yet.
  const Json shots = state_->Snapshot()["shots"];
  for (auto it = shots.rbegin(); it != shots.rend(); ++it) {
    if ((*it)["kind"] != "shot" || (*it)["rejected"].get<bool>()) continue;
    const std::string command = kUndo + (*it)["file"].get<std::string>();
    if (std::find(commands_.begin(), commands_.end(), command) != commands_.end()) continue;
    commands_.push_back(command);
    wake_.notify_all();
    return "";
  }
  return "no flash shot to undo";
}

std::string ConsoleWork::RequestFinish() {
  if (options_.review) return "review: nothing is changed";
  std::lock_guard<std::mutex> hold(mutex_);
  if (finishing_) return "finish is under way or done";
  finishing_ = true;
  commands_.push_back("finish");
  wake_.notify_all();
  return "";
}

bool ConsoleWork::finished() const {
  std::lock_guard<std::mutex> hold(mutex_);
  return finished_;
}

void ConsoleWork::Stop() {
  {
    std::lock_guard<std::mutex> hold(mutex_);
    stopping_ = true;
    if (child_ > 0) ::kill(child_, SIGTERM);  // process stops as on Ctrl-C; the lock goes with the console
  }
  wake_.notify_all();
  if (camera_thread_.joinable()) camera_thread_.join();
  if (analysis_thread_.joinable()) analysis_thread_.join();
  if (camera_) camera_->Close();
}

// --- The camera's thread -------------------------------------------------------------------

void ConsoleWork::CaptureLoop() {
  std::string kind = "shot";
  for (;;) {
    CaptureOptions o;
    o.out = options_.session;
    o.resume = true;
    o.locked_by_caller = true;
    o.mode = options_.mode;
    o.shots = o.mode == CaptureMode::kRemote ? 0 : 100000;
    o.calibration = kind == "calib";
    o.settings = options_.settings;
    if (ConfigEntry subject; camera_->GetConfig("subject", &subject).ok())  // the virtual rig: what it shows
      o.settings.push_back(std::string("subject=") + (kind == "calib" ? "checkerboard" : "flash"));
    state_->Update([&](Json& s) { s["capture"] = {{"state", "waiting"}, {"kind", kind}, {"error", ""}}; },
                   {{"type", "capture"}, {"state", "waiting"}, {"kind", kind}});
    {
      std::lock_guard<std::mutex> hold(mutex_);
      reconcile_ = true;  // a resumed run may journal files a crash left: the page gets them too
    }
    // Enter mode: the run waits in WaitForShot. Remote mode: it ends when a command other than
    // undo is queued, which stays queued for the loop below.
    const ProgressFn progress = [this](int, int, const std::string&) {
      ReconcileWithJournal();
      std::unique_lock<std::mutex> hold(mutex_);
      if (stopping_) return false;
      if (options_.mode != CaptureMode::kRemote) return true;
      TakeUndos(hold);
      return commands_.empty();
    };
    auto report = RunCapture(*camera_, o, progress, [this, kind](int, int) { return WaitForShot(kind); },
                             [this](const CapturedShot& shot) { AfterShot(shot); });
    if (report.ok())
      if (Status st = WriteVirtualTruth(*camera_, *report, options_.session); !st.ok())
        state_->Update([&](Json& s) { s["notes"].push_back(st.message()); }, {{"type", "note"}});
    const std::string error = !report.ok() ? report.status().message() : report->error;
    std::unique_lock<std::mutex> hold(mutex_);
    if (!error.empty()) {
      hold.unlock();
      state_->Update([&](Json& s) { s["capture"] = {{"state", "error"}, {"kind", kind}, {"error", error}}; },
                     {{"type", "capture"}, {"state", "error"}, {"error", error}});
      hold.lock();
      for (;;) {  // the operator may still undo and finish with the shots taken
        wake_.wait(hold, [&] { return stopping_ || !commands_.empty(); });
        if (stopping_) return;
        TakeUndos(hold);
        if (finishing_) break;
        commands_.clear();  // shots: refused at the request already
      }
    }
    if (stopping_) return;
    const std::string next = commands_.empty() ? "" : commands_.front();
    if (!next.empty() && next != "shot" && next != "calib") commands_.pop_front();
    if (next == "finish" || (!error.empty() && finishing_)) {
      hold.unlock();
      Finish();
      return;
    }
    if (next == "shot" || next == "calib") {
      kind = next;
      if (options_.mode == CaptureMode::kRemote) commands_.pop_front();  // remote: the switch is the command
    }
  }
}

void ConsoleWork::TakeUndos(std::unique_lock<std::mutex>& hold) {
  while (!commands_.empty() && commands_.front().rfind(kUndo, 0) == 0) {
    const std::string file = commands_.front().substr(kUndo.size());
    commands_.pop_front();
    hold.unlock();
    UndoShot(file);
    hold.lock();
  }
}

// Shots the journal has and the page lacks (journaled by a resumed run's recovery) join the page
// and the analysis, once per capture run.
void ConsoleWork::ReconcileWithJournal() {
  {
    std::lock_guard<std::mutex> hold(mutex_);
    if (!reconcile_) return;
    reconcile_ = false;
  }
  auto session = Session::Open(options_.session);
  if (!session.ok()) return;
  const Json now = state_->Snapshot();
  std::set<std::string> shown;
  for (const Json& shot : now["shots"]) shown.insert(shot["file"].get<std::string>());
  for (const ShotRecord& r : session->shots()) {
    if (shown.count(r.file)) continue;
    state_->Update([&](Json& s) {
      Json entry = ShotEntry(r);
      entry["rejected"] = session->IsRejected(r.file);
      s["shots"].push_back(entry);
    }, {{"type", "shot"}, {"file", r.file}, {"kind", r.kind}});
    if (session->IsRejected(r.file)) continue;
    std::lock_guard<std::mutex> hold(mutex_);
    jobs_.push_back({r.kind, r.file});
    wake_.notify_all();
  }
}

bool ConsoleWork::WaitForShot(const std::string& kind) {
  ReconcileWithJournal();
  std::unique_lock<std::mutex> hold(mutex_);
  for (;;) {
    wake_.wait(hold, [&] { return stopping_ || !commands_.empty(); });
    if (stopping_) return false;
    TakeUndos(hold);
    if (commands_.empty()) continue;
    if (commands_.front() != kind) return false;  // left queued: the capture loop takes it
    commands_.pop_front();
    hold.unlock();
    if (kind == "shot" && options_.follow_guide) {  // the virtual photographer takes the first suggestion
      const Json next = state_->Snapshot()["next"];
      std::optional<Eigen::Vector3d> where;
      if (!next.empty()) where = JsonVector3d(next[0]["position_cam_m"], "position_cam_m", 100);
      HoldFlashAt(*camera_, where);
    }
    state_->Update([&](Json& s) { s["capture"]["state"] = "shooting"; }, {{"type", "capture"}, {"state", "shooting"}});
    return true;
  }
}

void ConsoleWork::UndoShot(const std::string& file) {
  auto session = Session::Open(options_.session);
  if (session.ok() && session->IsRejected(file)) return;
  const Status rejected = session.ok() ? session->RejectShot(file, "undone in the console") : session.status();
  if (!rejected.ok()) {
    state_->Update([&](Json& s) { s["notes"].push_back(rejected.message()); }, {{"type", "note"}});
    return;
  }
  state_->Update([&](Json& s) { (*FindShot(s, file))["rejected"] = true; }, {{"type", "undo"}, {"file", file}});
  std::lock_guard<std::mutex> hold(mutex_);
  jobs_.push_back({"undo", file});
  wake_.notify_all();
}

// Called by capture once the shot is in the session and journaled: the page hears of it at once;
// what it shows comes after the analysis.
void ConsoleWork::AfterShot(const CapturedShot& shot) {
  const auto t0 = std::chrono::steady_clock::now();
  ShotRecord record;
  record.index = shot.index;
  record.kind = shot.kind;
  record.file = shot.file;
  record.flags = shot.flags;
  record.time_utc = UtcNowIso8601();
  state_->Update([&](Json& s) {
    s["shots"].push_back(ShotEntry(record));
    s["capture"]["state"] = "waiting";
  }, {{"type", "shot"}, {"file", shot.file}, {"kind", shot.kind}});
  {
    std::lock_guard<std::mutex> hold(mutex_);
    jobs_.push_back({shot.kind, shot.file});
  }
  wake_.notify_all();
  // mesocap's own time for the shot: capture's (checks, fsync, journal) and the console's.
  const double console_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  state_->Update([&](Json& s) {
    if (Json* entry = FindShot(s, shot.file)) (*entry)["overhead_s"] = shot.overhead_s + console_s;
  }, {{"type", "timing"}, {"file", shot.file}});
}

// --- The analysis's thread ------------------------------------------------------------------

void ConsoleWork::AnalysisLoop() {
  for (;;) {
    Job job;
    {
      std::unique_lock<std::mutex> hold(mutex_);
      wake_.wait(hold, [&] { return stopping_ || !jobs_.empty(); });
      if (stopping_) return;
      job = jobs_.front();
      jobs_.pop_front();
      analysing_ = true;
    }
    Analyse(job);
    {
      std::lock_guard<std::mutex> hold(mutex_);
      analysing_ = false;
    }
    wake_.notify_all();
  }
}

void ConsoleWork::Analyse(const Job& job) {
  if (job.what == "undo") {
    if (guide_) RecordGuidance(job.file, guide_->AfterUndo(job.file), "undo");
    return;
  }
  WriteThumbnail(job.file);
  ShotGuidance g;
  g.shot = job.file;
  if (job.what == "shot" && options_.guide) {
    StartGuideIfNeeded();
    if (guide_) g = guide_->AfterShot(job.file);
  }
  RecordGuidance(job.file, g, "analysis");
}

void ConsoleWork::StartGuideIfNeeded() {
  if (guide_) return;
  auto session = Session::Open(options_.session);
  const size_t calib_shots = session.ok() ? session->ShotsOfKind("calib").size() : 0;
  if (calib_shots == guide_failed_at_calib_shots_) return;  // tried with these; more may come
  CaptureGuideOptions o = options_.guidance;
  o.session = options_.session;
  auto started = StartGuide(*camera_, o);
  if (started.ok()) {
    guide_ = std::move(*started);
    return;
  }
  guide_failed_at_calib_shots_ = calib_shots;
  const std::string note = "no guidance yet: " + started.status().message();
  state_->Update([&](Json& s) { s["notes"] = Json::array({note}); }, {{"type", "note"}});
}

// The shot as a browser shows it: a JPEG view for the page (also of RAW or EXR shots, and lighter
// than a full-size photo over the network) and a thumbnail for the list.
void ConsoleWork::WriteThumbnail(const std::string& file) {
  const SessionLayout layout(options_.session);
  auto image = ReadImage(options_.session / file);
  if (!image.ok()) return;  // the analysis says why the shot cannot be used
  Json urls = Json::object();
  for (const auto& [key, path, width] : {std::tuple{"image", layout.console_view(file), kViewWidth},
                                         std::tuple{"thumbnail", layout.console_thumbnail(file), kThumbnailWidth}}) {
    std::error_code ec;
    fs::create_directories(path.parent_path(), ec);
    const Image scaled = image->width() > width ? Thumbnail(*image, width) : *image;
    if (WriteImage(path, scaled, {.format = PixelFormat::kUint8Srgb, .jpeg_quality = 85}).ok()) urls[key] = FileUrl(layout, path);
  }
  state_->Update([&](Json& s) {
    if (Json* shot = FindShot(s, file)) shot->update(urls);
  }, {{"type", "thumbnail"}, {"file", file}});
}

// The shot's flash and whether calibration can use it; every earlier shot's once the rig is
// located (the locating calibration reads them all); the coverage and the next suggestions.
void ConsoleWork::RecordGuidance(const std::string& file, const ShotGuidance& g, const std::string& type) {
  const SessionLayout layout(options_.session);
  const std::string prefix = file + ": ";
  state_->Update([&](Json& s) {
    Json notes = Json::array();
    for (const std::string& m : g.missing)
      if (m.rfind(prefix, 0) != 0) notes.push_back(m);
    if (!g.rig_news.empty()) notes.push_back(g.rig_news);
    s["notes"] = notes;
    if (Json* shot = FindShot(s, file); shot && type != "undo") {
      (*shot)["analysed"] = true;
      (*shot)["seconds"] = g.seconds;
      for (const std::string& m : g.missing)
        if (m.rfind(prefix, 0) == 0) (*shot)["read_problems"].push_back(m.substr(prefix.size()));
      (*shot)["warnings"] = g.warnings;
      if ((*shot)["kind"] == "calib") (*shot)["note"] = "checkerboard: for the camera's intrinsics";
    }
    // Every flash shot's verdict anew: balls found later can give an earlier shot its flash, and
    // the flash of a shot can drop out when they are found again.
    std::map<std::string, std::string> calibration_flags;
    const BoardPose* top = nullptr;
    const bool located = guide_ && guide_->rig_located();
    if (located) {
      for (const ShotCalibration& c : guide_->rig().shots) calibration_flags[c.file] = c.light.ok ? "" : c.light.flag;
      top = TopBoardPose(guide_->rig());
    }
    for (Json& shot : s["shots"]) {
      if (shot["kind"] != "shot" || !shot["analysed"].get<bool>()) continue;
      const std::string name = shot["file"];
      const Json& problems = shot["read_problems"];
      const auto flash = located ? guide_->flashes().find(name) : std::map<std::string, Eigen::Vector3d>::const_iterator();
      shot["why_not"] = problems;
      if (located && flash != guide_->flashes().end()) {
        shot["flash"] = {{"position_cam_m", ToJson(flash->second)},
                         {"words", top ? FlashPositionWords(flash->second, {top->id, top->R, top->t, {}}) : ""}};
        shot["usable"] = problems.empty();
      } else {
        shot["flash"] = nullptr;
        shot["usable"] = located || !problems.empty() ? Json(false) : Json();  // null: not known until located
        if (located && problems.empty())
          shot["why_not"].push_back(calibration_flags.count(name) && !calibration_flags[name].empty()
                                        ? "no flash position: " + calibration_flags[name]
                                        : "no flash position from the balls");
      }
    }
    if (g.coverage) {
      s["coverage"] = CoverageSummaryJson(*g.coverage, FileUrl(layout, layout.coverage().plot()) + "?v=" +
                                                           std::to_string(s["version"].get<int64_t>() + 1));
      s["next"] = SuggestionsJson(*g.coverage);
    }
  }, {{"type", type}, {"file", file}});
}

// --- Finish: `mesocap process` under the console's lock --------------------------------------

void ConsoleWork::WaitForAnalysis() {
  std::unique_lock<std::mutex> hold(mutex_);
  wake_.wait(hold, [&] { return stopping_ || (jobs_.empty() && !analysing_); });
}

void ConsoleWork::Finish() {
  WaitForAnalysis();
  {
    std::lock_guard<std::mutex> hold(mutex_);
    if (stopping_) return;
  }
  const SessionLayout layout(options_.session);
  state_->Update([&](Json& s) {
    s["capture"]["state"] = "finished";
    s["process"]["state"] = "running";
    s["process"]["log"] = FileUrl(layout, layout.console_process_log());
  }, {{"type", "process"}, {"state", "running"}});
  std::error_code ec;
  fs::create_directories(layout.console(), ec);
  std::ofstream log(layout.console_process_log());
  std::vector<std::string> args = {fs::read_symlink("/proc/self/exe", ec).string(), "process", options_.session.string()};
  args.insert(args.end(), options_.process_args.begin(), options_.process_args.end());
  args.push_back("--no-progress");
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  int pipe_fds[2];
  int exit_code = -1;
  if (::pipe(pipe_fds) == 0) {
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, pipe_fds[1], 1);
    posix_spawn_file_actions_adddup2(&actions, pipe_fds[1], 2);
    posix_spawn_file_actions_addclose(&actions, pipe_fds[0]);
    posix_spawn_file_actions_addclosefrom_np(&actions, 3);  // not the server's sockets, nor the lock
    pid_t child = 0;
    // The child inherits MESOCAP_SESSION_LOCK: it works under the console's lock.
    int spawned = 0;
    {
      std::lock_guard<std::mutex> hold(mutex_);  // Stop() terminates it from now on
      spawned = stopping_ ? -1 : ::posix_spawn(&child, argv[0], &actions, nullptr, argv.data(), environ);
      if (spawned == 0) child_ = child;
    }
    posix_spawn_file_actions_destroy(&actions);
    ::close(pipe_fds[1]);
    FILE* out = spawned == 0 ? ::fdopen(pipe_fds[0], "r") : nullptr;
    if (!out) ::close(pipe_fds[0]);
    if (spawned == 0) {
      char* buffer = nullptr;
      size_t capacity = 0;
      for (ssize_t n; out && (n = ::getline(&buffer, &capacity, out)) >= 0;) {
        std::string line(buffer, size_t(n));
        while (!line.empty() && (line.back() == '\n' || line.back() == '\r')) line.pop_back();
        log << line << "\n" << std::flush;
        state_->Update([&](Json& s) {
          Json& lines = s["process"]["lines"];
          lines.push_back(line);
          if (lines.size() > kProcessLinesKept) lines.erase(lines.begin());
        }, {{"type", "process"}, {"line", line}});
      }
      std::free(buffer);
      if (out) std::fclose(out);
      int status = 0;
      if (::waitpid(child, &status, 0) == child && WIFEXITED(status)) exit_code = WEXITSTATUS(status);
      std::lock_guard<std::mutex> hold(mutex_);
      child_ = 0;
    } else {
      log << "cannot start " << args[0] << "\n";
    }
  }
  const bool ok = exit_code == 0;
  const Json report = fs::exists(layout.report_html()) && ok ? Json(FileUrl(layout, layout.report_html())) : Json();
  state_->Update([&](Json& s) {
    s["process"]["state"] = ok ? "done" : "failed";
    s["process"]["exit_code"] = exit_code;
    s["process"]["report"] = report;
  }, {{"type", "finished"}, {"ok", ok}, {"report", report}});
  std::lock_guard<std::mutex> hold(mutex_);
  finished_ = true;
  wake_.notify_all();
}

}  // namespace mesocap::app
