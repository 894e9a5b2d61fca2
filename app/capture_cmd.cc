// mesocap capture: tethered capture from a camera (libgphoto2) into a session folder; with
// --guide, after each flash shot, where the flash was and where it is still needed
// (app/capture_guide.h).
#include <signal.h>

#include <csignal>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "app/capture_guide.h"
#include "app/commands.h"
#include "capture/camera.h"
#include "capture/tethered_capture.h"
#include "capture/virtual_camera.h"
#include "core/atomic_file.h"
#include "core/progress.h"

namespace mesocap::app {
namespace {

struct CaptureArgs {
  CaptureOptions options;
  std::string camera_model, port, mode = "interval";
  bool show_config = false;
  CLI::Option* shots_option = nullptr;
  bool no_progress = false;
  bool guide = false, follow_guide = false;
  CaptureGuideOptions guidance = [] {
    CaptureGuideOptions o;
    o.coverage.suggestions = 3;
    return o;
  }();
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

// Guidance after each flash shot, started at the first one (the session exists by then). A guide
// that cannot start says why once; capture goes on without it.
AfterShotFn GuidanceAfterEachShot(CaptureArgs& args, Camera& camera) {
  auto guide = std::make_shared<std::unique_ptr<CaptureGuide>>();
  auto failed = std::make_shared<bool>(false);
  return [&args, &camera, guide, failed](const CapturedShot& shot) {
    if (shot.kind != "shot" || *failed) return;
    if (!*guide) {
      CaptureGuideOptions options = args.guidance;
      options.session = args.options.out;
      // The virtual rig knows its layout, as a lab keeps its pyramid's on file.
      if (auto* virtual_camera = dynamic_cast<VirtualCamera*>(&camera);
          virtual_camera && options.layout_file.empty() && !std::filesystem::exists(options.session / "rig_layout.json"))
        if (Status st = WriteJsonFile(options.session / "rig_layout.json", LayoutOf(virtual_camera->scene()).ToJson()); !st.ok())
          std::fprintf(stderr, "capture: %s\n", st.message().c_str());
      auto started = CaptureGuide::Start(options);
      if (!started.ok()) {
        *failed = true;
        std::fprintf(stderr, "capture: no guidance: %s\n", started.status().message().c_str());
        return;
      }
      *guide = std::move(*started);
    }
    const ShotGuidance guidance = (*guide)->AfterShot(shot.file);
    std::printf("%s\n", guidance.Text().c_str());
    std::fflush(stdout);
    if (!args.follow_guide) return;
    // The virtual photographer moves the flash where the guidance says, or holds it by hand.
    const bool suggested = guidance.coverage && !guidance.coverage->report.next.empty();
    const std::string where =
        suggested ? FlashPositionValue(guidance.coverage->report.next.front().position_cam) : kFlashHandHeld;
    if (CameraStatus st = camera.SetConfig(kFlashPositionSetting, where); !st.ok())
      std::fprintf(stderr, "capture: %s\n", st.message.c_str());
  };
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
    sub->add_flag("--guide", args->guide,
                  "After each flash shot, print where the flash was (from the balls) and where the next shots are "
                  "needed; SESSION/coverage/ shows it per board (as `mesocap coverage`)");
    sub->add_flag("--follow-guide", args->follow_guide,
                  "With --guide and the virtual rig: the virtual photographer moves the flash to the first suggestion");
    sub->add_option("--layout", args->guidance.layout_file, "Guidance: the rig layout (default SESSION/rig_layout.json)");
    sub->add_option("--camera-file", args->guidance.camera_file,
                    "Guidance: intrinsics (camera.json from calibrate-camera); default: from the session's calib/ shots");
    sub->add_option("--guide-after", args->guidance.locate_after_shots,
                    "Guidance: flash shots before the boards and balls are located (a full calibration, once)")
        ->capture_default_str();
    sub->add_option("--suggest", args->guidance.coverage.suggestions, "Guidance: next flash positions listed")
        ->capture_default_str();
  };
  c.run = [args]() {
    CaptureOptions& o = args->options;
    if (!StringToCaptureMode(args->mode, &o.mode))
      return Fail("capture", "--mode must be interval, enter or remote, not '" + args->mode + "'", kExitUsage);
    if (o.mode == CaptureMode::kRemote && args->shots_option->count() == 0) o.shots = 0;
    if (args->follow_guide) args->guide = true;
    if (args->guide && o.calibration)
      return Fail("capture", "--guide follows flash shots; checkerboard shots (--calibration) need none", kExitUsage);
    if (args->guide)
      if (std::string why = args->guidance.Check(); !why.empty()) return Fail("capture", why, kExitUsage);
    if (!args->show_config)
      if (std::string why = o.Check(); !why.empty()) return Fail("capture", why, kExitUsage);

    auto camera = CreateCamera(args->camera_model, args->port);
    if (!camera.ok()) return Fail("capture", camera.status().message(), kExitFailure);
    if (CameraStatus st = ValidateSettings(**camera, o.settings); !st.ok())
      return Fail("capture", st.message, st.error == CameraError::kBadSetting ? kExitUsage : kExitFailure);
    if (ConfigEntry entry; args->follow_guide && !(*camera)->GetConfig(kFlashPositionSetting, &entry).ok())
      return Fail("capture", "--follow-guide needs a camera that places the flash itself (--camera virtual)", kExitUsage);
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
    ProgressBar bar("capture", !args->no_progress && !args->guide);  // guidance prints its lines instead
    int last_reported = 0;
    ProgressFn progress = [&](int done, int total, const std::string& what) {
      if (g_interrupted) return false;
      if (args->no_progress || args->guide) return true;
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
    auto report = RunCapture(**camera, o, progress, ready, args->guide ? GuidanceAfterEachShot(*args, **camera) : nullptr);
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
