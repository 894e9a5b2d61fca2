#include "app/console_args.h"

#include <CLI/CLI.hpp>

#include "core/session_layout.h"

namespace mesocap::app {

CLI::App* AddConsoleOptions(CLI::App& app, ConsoleArgs* args) {
  CLI::App* sub = app.add_subcommand(
      "console",
      "A live web page for a tethered capture session: the last shot, per board the light directions measured and "
      "still needed, where to hold the flash next, undo, and the finished material (docs/console.md)");
  sub->add_option("session", args->session, "Session folder: new (missing or empty), or existing with --resume or --review")
      ->required();
  sub->add_option("--camera", args->camera_model, "Camera model as `mesocap cameras` lists it (default: the one detected); `virtual`: the virtual rig; `fake`: a folder of photos (--port FOLDER)");
  sub->add_option("--port", args->port, "Camera port, as for `mesocap capture` (virtual:...,follow-error=E for a person's error in following the guide)");
  sub->add_option("--set", args->settings, "Camera setting key=value, repeatable (as for `mesocap capture`)");
  sub->add_flag("--resume", args->resume, "Continue an existing session (after a crash too): its shots stay, numbering goes on");
  sub->add_flag("--review", args->review, "Serve the page for a session without a camera (nothing is captured or changed)");
  sub->add_option("--mode", args->mode,
                  "enter: the page's button (or POST /api/shot) fires the camera; remote: the photographer fires it "
                  "(remote release) and each new file is taken")
      ->check(CLI::IsMember({"enter", "remote"}))
      ->capture_default_str();
  sub->add_option("--listen", args->listen,
                  "ADDRESS:PORT to serve on (port 0: any free one). Any address but loopback needs a token")
      ->capture_default_str();
  sub->add_option("--token", args->token,
                  "The token every request must carry (Authorization: Bearer TOKEN, or the page's cookie); default off "
                  "loopback: a random one, printed with the page's address");
  sub->add_option("--connections", args->threads, "Connections served at once (each open page's event stream holds one)")
      ->check(CLI::Range(4, 1024))
      ->capture_default_str();
  sub->add_flag("--no-guide", args->no_guide,
                "No guidance: the page shows the shots only (no flash positions, coverage or suggestions)");
  sub->add_flag("--follow-guide", args->follow_guide,
                "With the virtual rig: the virtual photographer holds the flash at the first suggestion");
  AddGuidanceOptions(sub, &args->guidance, &args->guide_images);
  sub->add_option("--process-args", args->process_args,
                  "Finish runs `mesocap process SESSION` with these options (one string, split at spaces), e.g. "
                  "\"--camera camera.json --slice-size 128\"");
  sub->add_flag("--exit-after-finish", args->exit_after_finish,
                "Exit once finish is done (default: keep serving the finished session until Ctrl-C)");
  return sub;
}

}  // namespace mesocap::app
