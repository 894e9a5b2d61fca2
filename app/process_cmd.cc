// mesocap process SESSION: every stage from the shots to the exports (app/process.h), a summary
// table and SESSION/report.html.
#include <cstdio>
#include <memory>

#include "app/commands.h"
#include "app/process.h"
#include "app/synth_output.h"

namespace mesocap::app {
namespace {

namespace fs = std::filesystem;

struct ProcessArgs {
  ProcessOptions options;
  std::string synth_size = "512x512";
  bool no_brdf_smoothing = false;
  std::string ptm_format = "rgb";
  bool no_progress = false;
};

int Run(ProcessArgs& a) {
  const std::string verb = "process";
  if (!StringToPtmFormat(a.ptm_format, &a.options.ptm.format))
    return Fail(verb, "--ptm-format must be lrgb or rgb, not '" + a.ptm_format + "'", kExitUsage);
  a.options.resample.brdf_smoothing = !a.no_brdf_smoothing;
  a.options.progress = !a.no_progress;
  if (!ParseSize(a.synth_size, &a.options.synth.width, &a.options.synth.height))
    return Fail(verb, "--synth-size '" + a.synth_size + "' is not WxH (1..32768 each)", kExitUsage);
  if (std::string why = a.options.Check(); !why.empty()) return Fail(verb, why, kExitUsage);
  auto outcomes = RunProcess(a.options);
  if (!outcomes.ok()) return Fail(verb, outcomes.status().message());
  PrintProcessSummary(*outcomes);
  if (Status st = WriteProcessReport(a.options.session, *outcomes); !st.ok()) return Fail(verb, st.message());
  std::printf("process: done -> %s\n", (a.options.session / "report.html").string().c_str());
  return kExitOk;
}

}  // namespace

Command ProcessCommand() {
  auto args = std::make_shared<ProcessArgs>();
  Command c;
  c.name = "process";
  c.setup = [args](CLI::App& app) {
    CLI::App* sub = app.add_subcommand(
        "process", "Run every stage on a session (calibrate, resample, fit-ptm, reconstruct, export), skipping unchanged ones");
    sub->add_option("session", args->options.session, "Session folder (from capture, import or simulate)")->required();
    sub->add_option("--camera", args->options.calibrate.camera_file,
                    "Intrinsics (camera.json from calibrate-camera); default: from the session's calib/ shots");
    sub->add_option("--layout", args->options.calibrate.layout_file, "Rig layout (default SESSION/rig_layout.json)");
    sub->add_option("--pose-shots", args->options.calibrate.calibrate.pose_shots, "Shots searched for AprilTags")->capture_default_str();
    sub->add_option("--marked-corners", args->options.calibrate.calibrate.marked_corners, "Hand-marked board corners (docs/formats.md)");
    sub->add_option("--slice-size", args->options.resample.slice_size, "Texels per side of each measured BTF slice")->capture_default_str();
    sub->add_flag("--no-brdf-smoothing", args->no_brdf_smoothing, "Do not rescale slices to the smoothed average BRDF");
    sub->add_option("--ptm-format", args->ptm_format, "PTM of each board: rgb or lrgb")->capture_default_str();
    sub->add_option("--btf-size", args->options.reconstruct.slices.size, "Texels per side of the reconstructed BTF (power of two)")
        ->capture_default_str();
    sub->add_option("--btf-grid", args->options.reconstruct.grid, "Direction pairs of the reconstructed BTF: bonn (6561) or coarse (289)")
        ->capture_default_str();
    sub->add_flag("--btf-pixel-only", args->options.reconstruct.pixel_only, "Reconstruct from pixel histograms only (no subbands)");
    args->options.reconstruct.method.AddTo(sub, "--btf-");
    sub->add_option("--synth", args->options.synth.method,
                    "Also enlarge the reconstructed BTF: roller, quilt, ptm-block or texton (SESSION/synth/; export adds gltf_synth/)");
    sub->add_option("--synth-size", args->synth_size, "Size of the enlarged material, WxH texels")->capture_default_str();
    sub->add_option("--synth-seed", args->options.synth.seed, "Random seed of the synthesis")->capture_default_str();
    sub->add_option("--force", args->options.force, "Rerun this stage even if unchanged (repeatable; 'all' for every stage)");
    sub->add_option("--threads", args->options.threads, "Threads (-1: all cores)")->capture_default_str();
    sub->add_flag("--no-progress", args->no_progress, "Do not draw progress bars");
  };
  c.run = [args]() { return Run(*args); };
  return c;
}

}  // namespace mesocap::app
