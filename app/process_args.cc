#include "app/process_args.h"

#include <CLI/CLI.hpp>

#include "core/session_layout.h"

namespace mesocap::app {

CLI::App* AddProcessOptions(CLI::App& app, ProcessArgs* args) {
  const SessionLayout S = HelpLayout();
  CLI::App* sub = app.add_subcommand(
      "process", "Run every stage on a session (calibrate, resample, fit-ptm, reconstruct, export), skipping unchanged ones");
  sub->add_option("session", args->options.session, "Session folder (from capture, import or simulate)")->required();
  sub->add_option("--camera", args->options.calibrate.camera_file,
                  "Intrinsics (camera.json from calibrate-camera); default: from the session's " + FolderName(S.calib()) + " shots");
  sub->add_option("--layout", args->options.calibrate.layout_file, "Rig layout (default " + S.rig_layout().string() + ")");
  sub->add_option("--pose-shots", args->options.calibrate.calibrate.pose_shots, "Shots searched for AprilTags")->capture_default_str();
  sub->add_option("--marked-corners", args->options.calibrate.calibrate.marked_corners, "Hand-marked board corners (docs/formats.md)");
  sub->add_option("--slice-size", args->options.resample.slice_size, "Texels per side of each measured BTF slice")->capture_default_str();
  sub->add_flag("--no-brdf-smoothing", args->no_brdf_smoothing, "Do not rescale slices to the smoothed average BRDF");
  sub->add_flag("--no-chroma-detail", args->no_chroma_detail,
                "Resample JPEG shots with their colour as stored at half resolution, instead of restoring its detail from the brightness");
  sub->add_option("--ptm-format", args->ptm_format, "PTM of each board: rgb or lrgb")->capture_default_str();
  sub->add_option("--btf-size", args->options.reconstruct.slices.size, "Texels per side of the reconstructed BTF (power of two)")
      ->capture_default_str();
  sub->add_option("--btf-grid", args->options.reconstruct.grid, "Direction pairs of the reconstructed BTF: bonn (6561) or coarse (289)")
      ->capture_default_str();
  sub->add_flag("--btf-pixel-only", args->options.reconstruct.pixel_only, "Reconstruct from pixel histograms only (no subbands)");
  args->options.reconstruct.method.AddTo(sub, "--btf-");
  sub->add_option("--synth", args->options.synth.method,
                  "Also enlarge the reconstructed BTF: roller, quilt, ptm-block or texton (" + S.synth().root.string() +
                      "/; export adds " + FolderName(S.exports().gltf_synth().root) + ")");
  sub->add_option("--synth-size", args->synth_size, "Size of the enlarged material, WxH texels")->capture_default_str();
  sub->add_option("--synth-seed", args->options.synth.seed, "Random seed of the synthesis")->capture_default_str();
  sub->add_option("--decorate", args->options.decorate.meshes,
                  "Also dress this mesh (repeatable: OBJ, PLY, glTF, ...) in the reconstructed BTF, after export (" +
                      S.decorate_root().string() + "/<mesh name>/: the surface map, previews, a light sweep, a glTF asset)");
  sub->add_option("--decorate-method", args->options.decorate.methods,
                  "How --decorate dresses: texton (per vertex, <mesh name>/), quilt (per atlas texel, <mesh name>-quilt/), or both "
                  "given twice")
      ->capture_default_str();
  sub->add_option("--stage", args->options.only_stage,
                  "Run this one stage only, as the workflow does (its earlier stages must have run; docs/workflow.md)");
  sub->add_option("--shard", args->shard,
                  "With --stage reconstruct, synth or export: run shard I/N of it into " + S.shards_root().string() +
                      "/ (the first shard makes what all share: the statistics, the map, the GGX fit's observations; "
                      "merge with --merge N)");
  sub->add_option("--merge", args->options.merge_shards,
                  "With --stage reconstruct, synth or export: merge its N shards into the stage's folder, as one run would write it");
  sub->add_option("--outcome", args->outcome,
                  "On success, write what each stage did (JSON: stage, status, seconds, outputs) to this file, atomically "
                  "(the workflow's marker of a finished job)");
  sub->add_option("--force", args->options.force, "Rerun this stage even if unchanged (repeatable; 'all' for every stage)");
  sub->add_option("--threads", args->options.threads, "Threads (-1: all cores)")->capture_default_str();
  sub->add_flag("--no-progress", args->no_progress, "Do not draw progress bars");
  return sub;
}

}  // namespace mesocap::app
