// mesocap capture: tethered capture from a camera (libgphoto2) into a session folder.
// Not yet registered: the lead adds CaptureCommand() to app/commands.{h,cc} and this file to
// app/CMakeLists.txt.
#include <signal.h>

#include <csignal>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "app/commands.h"
#include "capture/camera.h"
#include "capture/tethered_capture.h"
#include "core/progress.h"

namespace mesocap::app {
namespace {

struct CaptureArgs {
  CaptureOptions options;
  std::string camera_model, port, mode = "interval";
  bool show_config = false;
  CLI::Option* shots_option = nullptr;
  bool no_progress = false;
};

volatile std::sig_atomic_t g_interrupted = 0;
void OnInterrupt(int) { g_interrupted = 1; }

// Prints every configuration entry: "name = value  (label; choices)".
void PrintConfig(const std::vector<ConfigEntry>& entries) {
  for (const auto& e : entries) {
    std::string choices;
    for (const auto& c : e.choices) choices += (choices.empty() ? "" : ", ") + c;
    std::printf("%-28s = %-20s  (%s%s%s)\n", e.name.c_str(), e.value.c_str(), e.label.c_str(),
                e.read_only ? "; read-only" : "", choices.empty() ? "" : ("; choices: " + choices).c_str());
  }
}

}  // namespace

Command CaptureCommand() {
  auto args = std::make_shared<CaptureArgs>();
  Command c;
  c.name = "capture";
  c.setup = [args](CLI::App& app) {
    CLI::App* sub = app.add_subcommand("capture", "Tethered capture from a camera (libgphoto2) into a session");
    CaptureOptions& o = args->options;
    sub->add_option("--out", o.out, "Session folder: new (must not exist or be empty), or existing with --resume");
    sub->add_option("--camera", args->camera_model, "Camera model as `mesocap cameras` lists it (default: the one detected); `virtual`: the virtual rig; `fake`: serve a folder of photos (--port FOLDER)");
    sub->add_option("--port", args->port, "Port as `mesocap cameras` lists it, e.g. usb:001,004; with --camera virtual: virtual:seed=S,material=M,width=W,height=H,shots=N,calib-shots=C,format=F");
    args->shots_option = sub->add_option("--shots", o.shots, "Pictures to take (remote mode: 0, its default, = until Ctrl-C)")
                             ->capture_default_str();
    sub->add_option("--interval", o.interval_s, "Seconds from one shot's start to the next (interval mode)")
        ->capture_default_str();
    sub->add_option("--set", o.settings,
                    "Camera setting key=value, repeatable (iso, shutterspeed, f-number, imageformat, "
                    "capturetarget, flashmode ... as the body names them); a wrong key or value lists the choices");
    sub->add_flag("--calibration", o.calibration, "Checkerboard shots: into calib/ instead of shots/");
    sub->add_flag("--resume", o.resume, "Add to an existing session, numbering after its last shot");
    sub->add_option("--mode", args->mode,
                    "interval: N shots, one every --interval s; enter: one shot per Enter key; remote: the "
                    "photographer fires the camera and each new file is downloaded")
        ->capture_default_str();
    sub->add_option("--idle-timeout", o.remote_idle_timeout_s,
                    "Remote mode: stop after this many seconds without a new file (0: never)")
        ->capture_default_str();
    sub->add_flag("--delete-from-camera", o.delete_from_camera,
                  "Delete each file from the camera once it is safely in the session");
    sub->add_flag("--show-config", args->show_config, "Print the camera's configuration (after --set) and exit");
    sub->add_flag("--no-progress", args->no_progress, "Do not draw a progress bar");
  };
  c.run = [args]() {
    CaptureOptions& o = args->options;
    if (!StringToCaptureMode(args->mode, &o.mode))
      return Fail("capture", "--mode must be interval, enter or remote, not '" + args->mode + "'", kExitUsage);
    if (o.mode == CaptureMode::kRemote && args->shots_option->count() == 0) o.shots = 0;
    if (!args->show_config)
      if (std::string why = o.Check(); !why.empty()) return Fail("capture", why, kExitUsage);

    auto camera = CreateCamera(args->camera_model, args->port);
    if (!camera.ok()) return Fail("capture", camera.status().message(), kExitFailure);
    if (CameraStatus st = ValidateSettings(**camera, o.settings); !st.ok())
      return Fail("capture", st.message, st.error == CameraError::kBadSetting ? kExitUsage : kExitFailure);
    if (args->show_config) {
      for (const auto& s : o.settings) {
        const size_t eq = s.find('=');
        if (CameraStatus st = (*camera)->SetConfig(s.substr(0, eq), s.substr(eq + 1)); !st.ok())
          return Fail("capture", st.message, st.error == CameraError::kBadSetting ? kExitUsage : kExitFailure);
      }
      std::vector<ConfigEntry> entries;
      if (CameraStatus st = (*camera)->ListConfig(&entries); !st.ok()) return Fail("capture", st.message);
      std::printf("%s on %s\n", (*camera)->info().model.c_str(), (*camera)->info().port.c_str());
      PrintConfig(entries);
      return kExitOk;
    }

    // Ctrl-C stops after the current shot; everything taken so far stays in the session. No
    // SA_RESTART, so a pending read of the Enter key returns at once.
    g_interrupted = 0;
    struct sigaction on_interrupt {}, previous {};
    on_interrupt.sa_handler = OnInterrupt;
    sigemptyset(&on_interrupt.sa_mask);
    ::sigaction(SIGINT, &on_interrupt, &previous);
    ProgressBar bar("capture", !args->no_progress);
    int last_reported = 0;
    ProgressFn progress = [&](int done, int total, const std::string& what) {
      if (g_interrupted) return false;
      if (args->no_progress) return true;
      if (total > 0) return bar.Update(done, total, what);
      if (done > last_reported) {  // remote mode without a count: one line per shot
        last_reported = done;
        std::fprintf(stderr, "capture [%d] %s\n", done, what.c_str());
      }
      return true;
    };
    ReadyFn ready = [](int number, int total) {
      std::fprintf(stderr, "shot %d of %d: press Enter to shoot (q and Enter to stop) ", number, total);
      std::string line;
      if (g_interrupted || !std::getline(std::cin, line)) return false;
      return line != "q" && line != "Q" && !g_interrupted;
    };
    auto report = RunCapture(**camera, o, progress, ready);
    ::sigaction(SIGINT, &previous, nullptr);
    (*camera)->Close();
    if (!report.ok()) return Fail("capture", report.status().message(), kExitFailure);
    std::printf("%s\n", report->Brief().c_str());
    if (!report->ok()) return Fail("capture", report->error, kExitFailure);
    if (report->stop_reason == "cancelled" && o.mode != CaptureMode::kEnter) return kExitCancelled;
    return kExitOk;
  };
  return c;
}

}  // namespace mesocap::app
