#include "app/console_work.h"

#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <chrono>
#include <fstream>

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

constexpr int kThumbnailWidth = 320;
constexpr size_t kProcessLinesKept = 400;

std::string FileUrl(const SessionLayout& layout, const fs::path& path) { return "/files/" + layout.Relative(path); }

Json ShotEntry(const ShotRecord& r) {
  Json why_not = Json::array();
  const bool not_fired = std::find(r.flags.begin(), r.flags.end(), "flash_not_fired") != r.flags.end();
  if (not_fired) why_not.push_back("the flash did not fire (the photo's EXIF says so)");
  return {{"file", r.file}, {"kind", r.kind}, {"index", r.index}, {"time_utc", r.time_utc},
          {"image", "/files/" + r.file}, {"thumbnail", "/files/" + r.file}, {"flags", r.flags},
          {"usable", not_fired ? Json(false) : Json()}, {"why_not", why_not}, {"warnings", Json::array()}, {"flash", nullptr},
          {"rejected", false}, {"analysed", false}};
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
      state["shots"].push_back(entry);
    }
  }
  if (auto coverage = ReadJsonFile(layout.coverage().assessment()); review && coverage.ok() && coverage->is_object()) {
    const int covered = coverage->value("covered", 0), reachable = coverage->value("reachable", 0);
    state["coverage"] = {{"covered", covered}, {"reachable", reachable},
                         {"percent", reachable ? 100.0 * covered / reachable : 100.0}, {"boards", Json::array()},
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
  const Json shots = state_->Snapshot()["shots"];
  const size_t undos = size_t(std::count(commands_.begin(), commands_.end(), "undo"));
  size_t undoable = 0;
  for (const Json& shot : shots) undoable += shot["kind"] == "shot" && !shot["rejected"].get<bool>();
  if (undoable <= undos) return "no flash shot to undo";
  commands_.push_back("undo");
  wake_.notify_all();
  return "";
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
    // Enter mode: the run waits in WaitForShot; remote mode: it stops for the next command.
    const ProgressFn progress = [this](int, int, const std::string&) {
      std::unique_lock<std::mutex> hold(mutex_);
      if (stopping_) return false;
      if (options_.mode != CaptureMode::kRemote || commands_.empty()) return true;
      pending_ = commands_.front();
      commands_.pop_front();
      if (pending_ != "undo") return false;
      pending_.clear();
      hold.unlock();
      UndoLastShot();
      return true;
    };
    auto report = RunCapture(*camera_, o, progress, [this, kind](int, int) { return WaitForShot(kind); },
                             [this](const CapturedShot& shot) { AfterShot(shot); });
    if (report.ok())
      if (Status st = WriteVirtualTruth(*camera_, *report, options_.session); !st.ok())
        state_->Update([&](Json& s) { s["notes"].push_back(st.message()); }, {{"type", "note"}});
    std::string next;
    {
      std::lock_guard<std::mutex> hold(mutex_);
      next = pending_;
      pending_.clear();
    }
    const std::string error = !report.ok() ? report.status().message() : report->error;
    if (!error.empty()) {
      state_->Update([&](Json& s) { s["capture"] = {{"state", "error"}, {"kind", kind}, {"error", error}}; },
                     {{"type", "capture"}, {"state", "error"}, {"error", error}});
      std::unique_lock<std::mutex> hold(mutex_);  // the operator may still finish with the shots taken
      wake_.wait(hold, [&] { return stopping_ || finishing_; });
      next = stopping_ ? "" : "finish";
    }
    if (next == "shot" || next == "calib") {
      kind = next;
      std::lock_guard<std::mutex> hold(mutex_);
      commands_.push_front(next);
      continue;
    }
    if (next == "finish") Finish();
    return;
  }
}

bool ConsoleWork::WaitForShot(const std::string& kind) {
  std::unique_lock<std::mutex> hold(mutex_);
  for (;;) {
    wake_.wait(hold, [&] { return stopping_ || !commands_.empty(); });
    if (stopping_) return false;
    const std::string command = commands_.front();
    commands_.pop_front();
    if (command == "undo") {
      hold.unlock();
      UndoLastShot();
      hold.lock();
      continue;
    }
    if (command != kind) {
      pending_ = command;
      return false;
    }
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

void ConsoleWork::UndoLastShot() {
  std::string file;
  const Json now = state_->Snapshot();
  for (const Json& shot : now["shots"])
    if (shot["kind"] == "shot" && !shot["rejected"].get<bool>()) file = shot["file"];
  if (file.empty()) return;
  auto session = Session::Open(options_.session);
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

void ConsoleWork::WriteThumbnail(const std::string& file) {
  const SessionLayout layout(options_.session);
  auto image = ReadImage(options_.session / file);
  if (!image.ok()) return;  // the analysis says why the shot cannot be used
  const fs::path thumb = layout.console_thumbnail(file);
  std::error_code ec;
  fs::create_directories(thumb.parent_path(), ec);
  if (!WriteImage(thumb, Thumbnail(*image, kThumbnailWidth), {.format = PixelFormat::kUint8Srgb, .jpeg_quality = 85}).ok()) return;
  const std::string url = FileUrl(layout, thumb);
  state_->Update([&](Json& s) {
    if (Json* shot = FindShot(s, file)) (*shot)["thumbnail"] = url;
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
        if (m.rfind(prefix, 0) == 0) (*shot)["why_not"].push_back(m.substr(prefix.size()));
      (*shot)["warnings"] = g.warnings;
      if ((*shot)["kind"] == "calib") (*shot)["note"] = "checkerboard: for the camera's intrinsics";
    }
    if (guide_ && guide_->rig_located()) {
      std::map<std::string, std::string> calibration_flags;
      for (const ShotCalibration& c : guide_->rig().shots) calibration_flags[c.file] = c.light.ok ? "" : c.light.flag;
      const BoardPose* top = TopBoardPose(guide_->rig());
      for (Json& shot : s["shots"]) {
        if (shot["kind"] != "shot" || shot["rejected"].get<bool>() || !shot["analysed"].get<bool>()) continue;
        const std::string name = shot["file"];
        if (auto it = guide_->flashes().find(name); it != guide_->flashes().end()) {
          shot["flash"] = {{"position_cam_m", ToJson(it->second)},
                           {"words", top ? FlashPositionWords(it->second, {top->id, top->R, top->t, {}}) : ""}};
          shot["usable"] = shot["why_not"].empty();
        } else if (shot["usable"].is_null()) {
          shot["usable"] = false;
          if (shot["why_not"].empty())
            shot["why_not"].push_back(calibration_flags.count(name) && !calibration_flags[name].empty()
                                          ? "no flash position: " + calibration_flags[name]
                                          : "no flash position from the balls");
        }
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
    const int spawned = ::posix_spawn(&child, argv[0], &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    ::close(pipe_fds[1]);
    if (spawned == 0) {
      FILE* out = ::fdopen(pipe_fds[0], "r");
      char buffer[4096];
      while (out && std::fgets(buffer, sizeof buffer, out)) {
        std::string line = buffer;
        while (!line.empty() && (line.back() == '\n' || line.back() == '\r')) line.pop_back();
        log << line << "\n" << std::flush;
        state_->Update([&](Json& s) {
          Json& lines = s["process"]["lines"];
          lines.push_back(line);
          if (lines.size() > kProcessLinesKept) lines.erase(lines.begin());
        }, {{"type", "process"}, {"line", line}});
      }
      if (out) std::fclose(out);
      int status = 0;
      if (::waitpid(child, &status, 0) == child && WIFEXITED(status)) exit_code = WEXITSTATUS(status);
    } else {
      ::close(pipe_fds[0]);
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
