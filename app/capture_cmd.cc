// mesocap capture: tethered capture from a camera (libgphoto2) into a session folder; with
// --guide, after each flash shot, where the flash was and where it is still needed
// (app/capture_guide.h).
#include "app/capture_args.h"

#include <signal.h>

#include <csignal>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "app/capture_guide.h"
#include "app/guided_capture.h"
#include "app/commands.h"
#include "capture/camera.h"
#include "capture/tethered_capture.h"
#include "capture/virtual_camera.h"
#include "core/atomic_file.h"
#include "core/json.h"
#include "core/progress.h"
#include "core/session.h"
#include "core/session_layout.h"

namespace mesocap::app {
namespace {

namespace fs = std::filesystem;

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
      auto started = StartGuide(camera, options);
      if (!started.ok()) {
        *failed = true;
        std::fprintf(stderr, "capture: no guidance: %s\n", started.status().message().c_str());
        return;
      }
      *guide = std::move(*started);
      std::printf("guidance: %s\n", HeldImagesWords(options.coverage.images).c_str());
    }
    const ShotGuidance guidance = (*guide)->AfterShot(shot.file);
    std::printf("%s\n", guidance.Text().c_str());
    std::fflush(stdout);
    if (!args.follow_guide) return;
    // The virtual photographer moves the flash where the guidance says, or holds it by hand.
    std::optional<Eigen::Vector3d> next;
    if (guidance.coverage && !guidance.coverage->report.next.empty()) next = guidance.coverage->report.next.front().position_cam;
    if (CameraStatus st = HoldFlashAt(camera, next); !st.ok()) std::fprintf(stderr, "capture: %s\n", st.message.c_str());
  };
}

}  // namespace

int RunCapture(CaptureArgs& a) {
  CaptureOptions& o = a.options;
  if (!StringToCaptureMode(a.mode, &o.mode))
    return Fail("capture", "--mode must be interval, enter or remote, not '" + a.mode + "'", kExitUsage);
  if (o.mode == CaptureMode::kRemote && a.shots_option->count() == 0) o.shots = 0;
  if (a.follow_guide) a.guide = true;
  if (a.guide && o.calibration)
    return Fail("capture", "--guide follows flash shots; checkerboard shots (--calibration) need none", kExitUsage);
  if (a.guide)
    if (std::string why = a.guidance.Check(); !why.empty()) return Fail("capture", why, kExitUsage);
  a.guidance.coverage.images = MirrorImagesNamed(a.guide_images);
  if (!a.show_config)
    if (std::string why = o.Check(); !why.empty()) return Fail("capture", why, kExitUsage);

  auto camera = CreateCamera(a.camera_model, a.port);
  if (!camera.ok()) return Fail("capture", camera.status().message(), kExitFailure);
  if (CameraStatus st = ValidateSettings(**camera, o.settings); !st.ok())
    return Fail("capture", st.message, st.error == CameraError::kBadSetting ? kExitUsage : kExitFailure);
  if (ConfigEntry entry; a.follow_guide && !(*camera)->GetConfig(kFlashPositionSetting, &entry).ok())
    return Fail("capture", "--follow-guide needs a camera that places the flash itself (--camera virtual)", kExitUsage);
  if (a.show_config) {
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
  ProgressBar bar("capture", !a.no_progress && !a.guide);  // guidance prints its lines instead
  int last_reported = 0;
  ProgressFn progress = [&](int done, int total, const std::string& what) {
    if (g_interrupted) return false;
    if (a.no_progress || a.guide) return true;
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
  auto report = mesocap::RunCapture(**camera, o, progress, ready, a.guide ? GuidanceAfterEachShot(a, **camera) : nullptr);
  ::sigaction(SIGINT, &previous, nullptr);
  if (report.ok())
    if (Status st = WriteVirtualTruth(**camera, *report, o.out); !st.ok()) std::fprintf(stderr, "capture: %s\n", st.message().c_str());
  (*camera)->Close();
  if (!report.ok()) return Fail("capture", report.status().message(), kExitFailure);
  std::printf("%s\n", report->Brief().c_str());
  // The images the guidance counted are the ones the reconstruction may use (BtfMethodArgs::
  // TakeSessionMirrorImages): from a guided session's spread-out lights its own check can pass a
  // wrong one.
  if (!a.guide_images.empty())
    if (auto session = Session::Open(o.out); session.ok())
      if (Status st = session->UpdateManifest({{"mirror_images", a.guide_images}}); !st.ok())
        std::fprintf(stderr, "capture: %s\n", st.message().c_str());
  if (!report->ok()) return Fail("capture", report->error, kExitFailure);
  if (report->stop_reason == "cancelled" && o.mode != CaptureMode::kEnter) return kExitCancelled;
  return kExitOk;
}
}  // namespace mesocap::app
