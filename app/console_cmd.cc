// mesocap console: a live web page for a tethered capture session (docs/console.md). Holds the
// session's lock for its whole run (capture, and `process` at finish as its child), serves the
// page and its API (app/console_server.h) and does the work behind it (app/console_work.h).
#include "app/console_args.h"

#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <optional>
#include <csignal>
#include <cstdio>
#include <sstream>
#include <thread>

#include "app/commands.h"
#include "app/console_page.h"
#include "app/console_server.h"
#include "app/console_work.h"
#include "capture/camera.h"
#include "capture/tethered_capture.h"
#include "capture/virtual_camera.h"
#include "core/session.h"
#include "core/session_lock.h"

namespace mesocap::app {
namespace {

namespace fs = std::filesystem;

volatile std::sig_atomic_t g_stop = 0;
void OnStop(int) { g_stop = 1; }

// "HOST:PORT", "[V6]:PORT" or "PORT" (on 127.0.0.1).
bool ParseListen(const std::string& text, std::string* host, int* port) {
  std::string port_text = text;
  *host = "127.0.0.1";
  if (!text.empty() && text[0] == '[') {
    const size_t close = text.find("]:");
    if (close == std::string::npos) return false;
    *host = text.substr(1, close - 1);
    port_text = text.substr(close + 2);
  } else if (const size_t colon = text.rfind(':'); colon != std::string::npos) {
    *host = text.substr(0, colon);
    port_text = text.substr(colon + 1);
  }
  if (host->empty() || port_text.empty() || port_text.find_first_not_of("0123456789") != std::string::npos) return false;
  *port = std::stoi(port_text.substr(0, 6));
  return *port >= 0 && *port <= 65535;
}

std::vector<std::string> SplitWords(const std::string& text) {
  std::istringstream words(text);
  std::vector<std::string> out;
  for (std::string w; words >> w;) out.push_back(w);
  return out;
}

}  // namespace

int RunConsole(ConsoleArgs& a) {
  ConsoleServerOptions server;
  if (!ParseListen(a.listen, &server.host, &server.port))
    return Fail("console", "--listen must be ADDRESS:PORT, not '" + a.listen + "'", kExitUsage);
  server.token = a.token.empty() && !IsLoopbackHost(server.host) ? RandomToken() : a.token;
  server.threads = a.threads;
  server.session = a.session;
  ConsoleWorkOptions work;
  work.session = fs::absolute(a.session).lexically_normal();
  work.review = a.review;
  work.mode = a.mode == "remote" ? CaptureMode::kRemote : CaptureMode::kEnter;
  work.settings = a.settings;
  work.guide = !a.no_guide;
  work.follow_guide = a.follow_guide;
  if (a.no_guide && a.follow_guide) return Fail("console", "--follow-guide follows the guidance --no-guide turns off", kExitUsage);
  work.guidance = a.guidance;
  work.guidance.coverage.images = MirrorImagesNamed(a.guide_images);
  work.process_args = SplitWords(a.process_args);
  if (a.review && a.resume) return Fail("console", "--review shows a session as it is; --resume captures more into it", kExitUsage);
  if (std::string why = work.guidance.Check(); !why.empty()) return Fail("console", why, kExitUsage);
  const bool exists = fs::exists(SessionLayout(work.session).manifest());
  if ((a.review || a.resume) && !exists)
    return Fail("console", a.session.string() + ": not a mesocap session (no " +
                                  SessionLayout(a.session).manifest().filename().string() + ")", kExitUsage);
  if (!a.review && !a.resume && !IsMissingOrEmptyDir(work.session))
    return Fail("console", a.session.string() + ": exists and is not empty; choose a new folder, or add --resume or --review", kExitUsage);

  std::unique_ptr<Camera> camera;
  if (!a.review) {
    auto opened = CreateCamera(a.camera_model, a.port);
    if (!opened.ok()) return Fail("console", opened.status());
    camera = std::move(*opened);
    if (CameraStatus st = ValidateSettings(*camera, a.settings); !st.ok())
      return Fail("console", st.message, st.error == CameraError::kBadSetting ? kExitUsage : kExitFailure);
    if (ConfigEntry entry; a.follow_guide && !camera->GetConfig(kFlashPositionSetting, &entry).ok())
      return Fail("console", "--follow-guide needs a camera that places the flash itself (--camera virtual)", kExitUsage);
  }

  // The server is listening before the session is touched: a busy port leaves nothing behind.
  ConsoleState state(InitialConsoleState(work.session, a.review));
  std::unique_ptr<ConsoleWork> worker;
  std::atomic<ConsoleWork*> live{nullptr};
  const auto ask = [&live](auto request) -> std::string {
    ConsoleWork* w = live.load();
    return w ? request(*w) : "the console is starting";
  };
  ConsoleActions actions;
  actions.shot = [ask] { return ask([](ConsoleWork& w) { return w.RequestShot("shot"); }); };
  actions.calibration_shot = [ask] { return ask([](ConsoleWork& w) { return w.RequestShot("calib"); }); };
  actions.undo = [ask] { return ask([](ConsoleWork& w) { return w.RequestUndo(); }); };
  actions.finish = [ask] { return ask([](ConsoleWork& w) { return w.RequestFinish(); }); };
  auto serving = ConsoleServer::Start(server, &state, actions, ConsolePage(work.session.filename().string()));
  if (!serving.ok()) return Fail("console", serving.status());
  g_stop = 0;
  struct sigaction on_stop {}, previous_int {}, previous_term {};
  on_stop.sa_handler = OnStop;
  sigemptyset(&on_stop.sa_mask);
  ::sigaction(SIGINT, &on_stop, &previous_int);
  ::sigaction(SIGTERM, &on_stop, &previous_term);
  const auto restore_signals = [&] {
    ::sigaction(SIGINT, &previous_int, nullptr);
    ::sigaction(SIGTERM, &previous_term, nullptr);
  };

  std::optional<SessionLock> lock;
  if (!a.review) {
    if (!exists) {
      CaptureOptions o;
      o.out = work.session;
      o.settings = a.settings;
      if (auto created = Session::Create(work.session, CaptureManifest(camera->info(), o)); !created.ok()) {
        (*serving)->Stop();
        restore_signals();
        return Fail("console", created.status());
      }
    }
    auto taken = SessionLock::Acquire(work.session, "console");
    if (!taken.ok()) {
      (*serving)->Stop();
      restore_signals();
      return Fail("console", taken.status());
    }
    lock.emplace(std::move(*taken));
  }
  worker = std::make_unique<ConsoleWork>(work, std::move(camera), &state);
  live = worker.get();
  std::printf("mesocap console: %s on %s (Ctrl-C to stop)\n", work.session.string().c_str(), (*serving)->url().c_str());
  std::fflush(stdout);

  while (!g_stop && !(a.exit_after_finish && worker->finished()))
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  worker->Stop();
  state.Close();
  (*serving)->Stop();  // before the worker goes: no request reaches it after
  restore_signals();
  const Json final_state = state.Snapshot();
  if (final_state["process"]["state"] == "failed")
    return Fail("console", "finish: `mesocap process` failed (its lines: " +
                               SessionLayout(work.session).console_process_log().string() + ")");
  return kExitOk;
}

}  // namespace mesocap::app
