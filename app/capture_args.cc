#include "app/capture_args.h"

#include <CLI/CLI.hpp>

#include "core/session_layout.h"

namespace mesocap::app {

CLI::App* AddCaptureOptions(CLI::App& app, CaptureArgs* args) {
  const SessionLayout S = HelpLayout();
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
  sub->add_flag("--calibration", o.calibration, "Checkerboard shots: into " + FolderName(S.calib()) + " instead of " + FolderName(S.shots()));
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
                "needed; " + S.coverage().root.string() + "/ shows it per board (as `mesocap coverage`)");
  sub->add_flag("--follow-guide", args->follow_guide,
                "With --guide and the virtual rig: the virtual photographer moves the flash to the first suggestion");
  AddGuidanceOptions(sub, &args->guidance, &args->guide_images);
  return sub;
}

void AddGuidanceOptions(CLI::App* sub, CaptureGuideOptions* guidance, std::vector<std::string>* guide_images) {
  const SessionLayout S = HelpLayout();
  sub->add_option("--layout", guidance->layout_file, "Guidance: the rig layout (default " + S.rig_layout().string() + ")");
  sub->add_option("--camera-file", guidance->camera_file,
                  "Guidance: intrinsics (camera.json from calibrate-camera); default: from the session's " + FolderName(S.calib()) + " shots");
  sub->add_option("--guide-after", guidance->locate_after_shots,
                  "Guidance: flash shots before the boards and balls are located (a full calibration, once)")
      ->capture_default_str();
  sub->add_option("--suggest", guidance->coverage.suggestions, "Guidance: next flash positions listed")
      ->capture_default_str();
  const std::vector<std::string> image_names(kMirrorImageNames.begin(), kMirrorImageNames.end());
  sub->add_option("--guide-images", *guide_images,
                  "Guidance: images of the patch the material looks the same under, comma-separated; each board "
                  "also counts its lights' images (as `mesocap coverage` does where the session's slices show them "
                  "hold). Default: each board's own lights. The top board's slices tell only after 70-85 "
                  "hand-held shots (docs/reconstruction.md)")
      ->delimiter(',')
      ->check(CLI::IsMember(image_names));
}

}  // namespace mesocap::app
