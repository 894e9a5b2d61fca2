#include "app/synth_args.h"

#include <CLI/CLI.hpp>

#include "core/session_layout.h"

namespace mesocap::app {
namespace {

void AddCommonOptions(CLI::App* sub, SynthArgs& a, bool needs_size) {
  sub->add_option("--input", a.input, "Exemplar: an image, a BTF folder or its " + BtfFolder{}.index().string() + ", a session (its slices), or a .ptm")
      ->required();
  sub->add_option("--out", a.out, "Output folder (must not exist or be empty)")->required();
  if (needs_size) sub->add_option("--size", a.size, "Output texels, WxH")->capture_default_str();
  sub->add_option("--slices", a.slices, "BTF: slice indices to write, comma-separated, or all")->capture_default_str();
  sub->add_option("--board", a.exemplar.board, "Session slices: the board to use (-1: the most head-on)")->capture_default_str();
  sub->add_option("--threads", a.threads, "Threads (-1: all cores)")->capture_default_str();
  sub->add_flag("--no-progress", a.no_progress, "Do not draw progress bars");
}

void AddQuiltOptions(CLI::App* sub, SynthArgs& a) {
  sub->add_option("--seed", a.seed, "Random seed (same seed and threads, same map)")->capture_default_str();
  sub->add_option("--patch-radius", a.quilt.patch_radius, "Work-window radius r_w (0: min(32, sample/4))")->capture_default_str();
  sub->add_option("--rotations", a.quilt.rotations, "Rotated copies of the sample to match (Zhou: 72; 1: none)")->capture_default_str();
  sub->add_option("--seam-threshold", a.quilt.seam_threshold, "T_c as a multiple of the sample's neighbour step")->capture_default_str();
  sub->add_option("--randomness", a.quilt.randomness, "Kwatra's stochastic placement temperature (0: least cost)")->capture_default_str();
  sub->add_flag_callback("--inside-sample", [&a] { a.quilt.whole_sample = false; },
                         "quilt: keep work windows inside the sample, as Zhou (0.8-1.2x the time). By default a patch may "
                         "hang off the sample's edge, so its border band is used as often as its centre and the statistics "
                         "stay nearer the sample's (docs/synthesis.md)");
  sub->add_option("--usage-weight", a.quilt.usage_weight,
                  "quilt: weight of the sample's usage in the choice among near-best placements, so that no region of "
                  "the sample is drawn on more than its share (0: the least cost, as Zhou; 0.5 brings stochastic and "
                  "directional photographs' statistics nearer the sample's, at 1.4-2x the time)")
      ->capture_default_str();
  sub->add_option("--usage-tolerance", a.quilt.usage_tolerance,
                  "quilt: placements within this fraction of the least cost are weighed by their usage")
      ->capture_default_str();
  sub->add_option("--svd-components", a.exemplar.svd_components, "BTF: geometry maps kept from the SVD (Zhou: 40)")->capture_default_str();
}

void AddTextonOptions(CLI::App* sub, SynthArgs& a) {
  sub->add_option("--k", a.texton.k, "texton: k of the k-coherence search (Tong: 11; 1 keeps only coherent continuations)")
      ->capture_default_str();
  sub->add_option("--neighbourhood", a.texton.neighbourhood,
                  "texton: N, the N x N neighbourhood at a texel's level, spaced 2^level texels")
      ->capture_default_str();
  sub->add_option("--passes", a.texton.passes, "texton: correction passes per level, four sub-passes each (Lefebvre & Hoppe: 2)")
      ->capture_default_str();
  sub->add_option("--jitter", a.texton.jitter, "texton: upsampled coordinates move by up to this x the level's spacing")
      ->capture_default_str();
  sub->add_option("--textons", a.texton_analysis.textons, "texton: n_t, textons at the finest level (a quarter per level above)")
      ->capture_default_str();
  sub->add_option("--representative-slices", a.texton_analysis.representative_slices,
                  "texton: n_s, slices chosen by K-means whose filter responses are clustered")
      ->capture_default_str();
  sub->add_option("--levels", a.texton_analysis.levels, "texton: Gaussian stack levels (0: while the sample spans 3 steps of the coarsest spacing; on meshes 8)")->capture_default_str();
  sub->add_option("--texton-dimensions", a.texton_analysis.dimensions,
                  "texton: principal directions kept of the concatenated filter responses")
      ->capture_default_str();
  sub->add_option("--analysis", a.analysis, "texton: reuse a saved analysis (" + SynthFolder{}.textons().string() + " of an earlier run on this exemplar)");
  sub->add_option("--audit", a.texton.audit_fraction,
                  "texton: share of queries also answered by the full search (reports how often both agree)")
      ->capture_default_str();
}

}  // namespace

CLI::App* AddSynthOptions(CLI::App& app, SynthArgs* args) {
  CLI::App* sub = app.add_subcommand(
      "synth", "Enlarge a material: a texture-coordinate map by the BTF roller, graphcut quilting, block synthesis (ptm-block) "
               "or 3D textons with k-coherence search (texton)");
  sub->add_option("--method", args->method,
                  "roller (periodic materials: weaves, knits, tiles; it repeats one tile set), quilt, ptm-block or texton "
                  "(any material)")
      ->capture_default_str();
  AddCommonOptions(sub, *args, true);
  AddQuiltOptions(sub, *args);
  sub->add_option("--tiles", args->roller.tiles, "Roller: tiles with identical borders")->capture_default_str();
  sub->add_option("--block", args->block.block, "ptm-block: block side in texels (the paper: 30)")->capture_default_str();
  sub->add_option("--overlap", args->block.overlap, "ptm-block: overlap of neighbouring blocks (0: block / 6)")->capture_default_str();
  sub->add_option("--tolerance", args->block.tolerance,
                  "ptm-block: blocks within (1 + tolerance) of the best neighbourhood distance are admitted, the least used "
                  "tried first")
      ->capture_default_str();
  sub->add_option("--seam-limit", args->block.seam_limit,
                  "ptm-block: take the first admitted block whose cuts leave steps within this x the sample's mean "
                  "neighbour step (else the least erring; 0: the first)")
      ->capture_default_str();
  sub->add_option("--projections", args->block.projections, "ptm-block: basis vectors of the rejection search's lower bounds")
      ->capture_default_str();
  sub->add_flag("--brute-force", args->brute_force,
                "ptm-block: compute every candidate's distance (same result, slower); texton: the full search");
  sub->add_option("--bound-basis", args->block_basis,
                  "ptm-block: basis of the lower bounds: principal (the neighbourhoods' SVD) or walsh (Walsh-Hadamard)")
      ->capture_default_str();
  AddTextonOptions(sub, *args);
  return sub;
}

CLI::App* AddSynthApplyOptions(CLI::App& app, SynthArgs* args) {
  CLI::App* sub = app.add_subcommand("synth-apply", "Apply a synthesis map to another exemplar of the same sample");
  sub->add_option("--map", args->map, SynthFolder{}.map().string() + " written by synth or paint")->required();
  AddCommonOptions(sub, *args, false);
  return sub;
}

CLI::App* AddPaintOptions(CLI::App& app, SynthArgs* args) {
  CLI::App* sub = app.add_subcommand("paint", "Graphcut texture painting: put the sample's feature where a target mask says");
  AddCommonOptions(sub, *args, true);
  AddQuiltOptions(sub, *args);
  sub->add_option("--feature-mask", args->feature_mask, "Sample-size mask, white = the feature")->required();
  sub->add_option("--target-mask", args->target_mask, "Output-size mask, white = where the feature goes")->required();
  sub->add_option("--transition", args->paint.transition_width, "Width of m0's linear transition zone (texels)")->capture_default_str();
  sub->add_flag("--verbatim", args->paint.verbatim, "Copy the whole feature once instead of synthesizing it");
  return sub;
}

}  // namespace mesocap::app
