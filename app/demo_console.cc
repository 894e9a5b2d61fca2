#include "app/demo_console.h"

#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <future>
#include <regex>
#include <thread>

#include "core/json.h"
#include "core/session_layout.h"
#include "core/text_format.h"

// Last: a header it brings (resolv.h) defines _res, a name Eigen's templates use.
#include <httplib.h>

extern char** environ;

namespace mesocap::app {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

constexpr int kCalibrationShots = 10, kFlashShots = 20;
constexpr int kEarlyShot = 5, kMidwayShot = 15;  // the flash shots after which the page is photographed

// `mesocap console` as a child, its output in `log`; its pid, or an error.
StatusOr<pid_t> SpawnConsole(const fs::path& session, const fs::path& log) {
  std::error_code ec;
  std::vector<std::string> args = {
      fs::read_symlink("/proc/self/exe", ec).string(), "console", session.string(), "--camera", "virtual", "--port",
      "virtual:seed=7,width=900,height=600,shots=60,calib-shots=10,follow-error=0.02", "--listen", "127.0.0.1:0",
      "--follow-guide", "--guide-after", "5", "--process-args", "--slice-size 64 --btf-size 32 --btf-grid coarse"};
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  pid_t pid = 0;
  const int spawned = ::posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0) return Status::Error("cannot start " + args[0] + " console");
  return pid;
}

// The port the console printed in its log.
int ConsolePort(const fs::path& log) {
  const std::regex address(R"(on http://127\.0\.0\.1:(\d+)/)");
  for (const auto start = Clock::now(); Clock::now() - start < std::chrono::seconds(30);) {
    std::ifstream in(log);
    const std::string text((std::istreambuf_iterator<char>(in)), {});
    if (std::smatch m; std::regex_search(text, m, address)) return std::stoi(m[1]);
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return 0;
}

class Operator {
 public:
  explicit Operator(int port) : client_("127.0.0.1", port) { client_.set_read_timeout(30, 0); }
  Json State() {
    auto reply = client_.Get("/api/state");
    Json state = reply && reply->status == 200 ? Json::parse(reply->body, nullptr, false) : Json();
    return state.is_discarded() ? Json() : state;
  }
  bool Press(const std::string& path) {
    auto reply = client_.Post(path, "", "text/plain");
    return reply && reply->status == 202;
  }
  // The state once `ready` holds of it, or null after `seconds`.
  template <class Ready>
  Json WaitFor(Ready ready, int seconds) {
    for (const auto start = Clock::now(); Clock::now() - start < std::chrono::seconds(seconds);) {
      const Json state = State();
      if (state.is_object() && ready(state)) return state;
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    return Json();
  }

 private:
  httplib::Client client_;
};

size_t Analysed(const Json& state, const std::string& kind) {
  size_t n = 0;
  for (const Json& shot : state["shots"]) n += shot["kind"] == kind && shot["analysed"].get<bool>();
  return n;
}

// The page as it looks now, 1920 x 1080, from headless Chromium; false when it cannot.
bool Screenshot(int port, const fs::path& file) {
  const fs::path profile = fs::temp_directory_path() / ("mesocap-demo-chromium-" + std::to_string(::getpid()));
  const std::string command = "chromium --headless --no-sandbox --disable-gpu --hide-scrollbars --window-size=1920,1080 "
                              "--virtual-time-budget=3000 --user-data-dir='" + profile.string() + "' --screenshot='" +
                              file.string() + "' 'http://127.0.0.1:" + std::to_string(port) + "/#still' >/dev/null 2>&1";
  const int code = std::system(command.c_str());
  std::error_code ec;
  fs::remove_all(profile, ec);
  return code == 0 && fs::exists(file);
}

StatusOr<ConsoleRecording> RecordConsoleSession(const fs::path& out) {
  const auto started = Clock::now();
  ConsoleRecording rec;
  rec.session = out / "console_session";
  const fs::path log = out / "console.log";
  auto pid = SpawnConsole(rec.session, log);
  if (!pid.ok()) return pid.status();
  const auto stop = [&] {
    ::kill(*pid, SIGTERM);
    ::waitpid(*pid, nullptr, 0);
  };
  const int port = ConsolePort(log);
  if (port == 0) {
    stop();
    return Status::Error("the console did not start (see " + log.string() + ")");
  }
  Operator op(port);
  const auto shoot = [&](const std::string& path, const std::string& kind, size_t count) {
    return op.Press(path) && !op.WaitFor([&](const Json& s) { return Analysed(s, kind) == count; }, 60).is_null();
  };
  const auto picture = [&](const std::string& name, const std::string& caption) {
    if (Screenshot(port, out / name)) rec.pictures.push_back({name, caption});
  };
  bool ok = true;
  for (size_t i = 1; ok && i <= size_t(kCalibrationShots); ++i) ok = shoot("/api/calibration-shot", "calib", i);
  for (size_t i = 1; ok && i <= size_t(kFlashShots); ++i) {
    ok = shoot("/api/shot", "shot", i);
    const Json state = op.State();
    if (ok && !state["coverage"].is_null()) rec.coverage_percents.push_back(state["coverage"]["percent"].get<double>());
    if (i == kEarlyShot)
      picture("console_early.png", Format("After %d flash shots: the boards and balls are located, the guidance starts", kEarlyShot));
    if (i == kMidwayShot) picture("console_midway.png", Format("After %d flash shots, each held where the page said (within 2 cm)", kMidwayShot));
  }
  const auto t_finish = Clock::now();
  ok = ok && op.Press("/api/undo") && op.Press("/api/finish");
  const Json done = ok ? op.WaitFor([](const Json& s) { return s["process"]["state"] == "done" || s["process"]["state"] == "failed"; }, 600)
                       : Json();
  rec.finish_seconds = std::chrono::duration<double>(Clock::now() - t_finish).count();
  if (ok) picture("console_finished.png", "Finished: `mesocap process` ran from the page, which links its report");
  stop();
  if (!ok || done.is_null() || done["process"]["state"] != "done")
    return Status::Error("the console session did not complete (see " + log.string() + ")");
  rec.seconds = std::chrono::duration<double>(Clock::now() - started).count();
  return rec;
}

}  // namespace

std::future<StatusOr<ConsoleRecording>> StartConsoleRecording(const fs::path& out) {
  std::fprintf(stderr, "demo: the capture console, alongside (%d checkerboard and %d flash shots, the demo as the operator)\n",
               kCalibrationShots, kFlashShots);
  return std::async(std::launch::async, [out] { return RecordConsoleSession(out); });
}

void AddConsoleToReport(const ConsoleRecording& rec, Report* report) {
  const std::vector<double>& percents = rec.coverage_percents;
  report->Heading("Capture console");
  report->Paragraph(Format(
      "`mesocap console` ran a tethered session on the virtual camera, alongside the stages above (%.0f s); the demo was "
      "the operator, pressing the page's buttons through its API (docs/console.md) while the virtual photographer held "
      "the flash where the page said, missing by 2 cm: %d checkerboard shots, %d flash shots, the coverage of the "
      "reachable light directions rising from %.0f%% to %.0f%%, one undo, then finish, which ran `mesocap process` under "
      "the console's lock (%.0f s). The session: %s/.",
      rec.seconds, kCalibrationShots, kFlashShots, percents.empty() ? 0.0 : percents.front(), percents.empty() ? 0.0 : percents.back(),
      rec.finish_seconds, rec.session.filename().string().c_str()));
  if (rec.pictures.empty()) report->Paragraph("(No screenshots: headless Chromium is not installed.)");
  for (const auto& [file, caption] : rec.pictures) report->Picture(file, caption);
}

}  // namespace mesocap::app
