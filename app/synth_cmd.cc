// mesocap synth, synth-apply, paint: enlarge a material (synth/). Each finds a texture-coordinate
// map on the exemplar's compact features and applies it to every slice (or the image, or the PTM).
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "app/commands.h"
#include "app/synth_output.h"
#include "app/synth_run.h"
#include "core/image_io.h"
#include "core/json.h"
#include "core/progress.h"
#include "core/session.h"
#include "synth/exemplar.h"
#include "synth/quilt.h"
#include "synth/roller.h"

namespace mesocap::app {
namespace {

namespace fs = std::filesystem;

struct SynthArgs {
  std::string method = "quilt";
  fs::path input, out, map, feature_mask, target_mask;
  std::string size = "512x512", slices = "all";
  ExemplarOptions exemplar;
  QuiltOptions quilt;
  RollerOptions roller;
  BlockSynthesisOptions block;
  TextonAnalysisOptions texton_analysis;
  TextonSynthesisOptions texton;
  fs::path analysis;  // texton: a saved textons.exr to reuse
  bool brute_force = false;
  std::string block_basis = "principal";
  PaintOptions paint;
  uint32_t seed = 1;
  int threads = -1;
  bool no_progress = false;
};

// Checks shared by the three commands; returns a non-zero exit code on a bad option.
int CheckCommon(const std::string& verb, SynthArgs& a, int* width, int* height) {
  if (!a.out.empty() && !IsMissingOrEmptyDir(a.out)) return Fail(verb, a.out.string() + ": exists and is not empty", kExitUsage);
  if (width && !ParseSize(a.size, width, height))
    return Fail(verb, "--size '" + a.size + "' is not WxH (1..32768 each)", kExitUsage);
  a.exemplar.num_threads = a.threads;
  return 0;
}

StatusOr<Exemplar> Load(const SynthArgs& a, const std::string& verb) {
  ProgressBar bar("features", !a.no_progress);
  return LoadExemplar(a.input, a.exemplar, bar.AsCallback());
}

int Finish(const std::string& verb, const SynthMap& map, const Exemplar& e, const SynthArgs& a, Json report,
           std::function<Status(const fs::path&)> write_extra = nullptr) {
  SynthOutputRequest request;
  request.write_extra = std::move(write_extra);
  request.out = a.out;
  request.report = std::move(report);
  request.num_threads = a.threads;
  if (e.kind == ExemplarKind::kBtf && !ParseSliceList(a.slices, int(e.slices.size()), &request.slices))
    return Fail(verb, "--slices '" + a.slices + "' is not 'all' or indices 0.." + std::to_string(e.slices.size() - 1), kExitUsage);
  ProgressBar bar("writing", !a.no_progress);
  if (Status st = WriteSynthesisOutputs(map, e, request, bar.AsCallback()); !st.ok()) return Fail(verb, st.message());
  std::printf("%s: %s %dx%d from %s (%s, %dx%d) -> %s\n", verb.c_str(), map.method.c_str(), map.width, map.height,
              a.input.string().c_str(), ExemplarKindToString(e.kind).c_str(), e.width, e.height, a.out.string().c_str());
  return kExitOk;
}

int RunSynth(SynthArgs& a) {
  const std::string verb = "synth";
  if (!IsSynthMethod(a.method))
    return Fail(verb, "unknown method '" + a.method + "' (roller, quilt, ptm-block, texton)", kExitUsage);
  int width = 0, height = 0;
  if (int code = CheckCommon(verb, a, &width, &height)) return code;
  auto e = Load(a, verb);
  if (!e.ok()) return Fail(verb, e.status().message());
  SynthMethodOptions method;
  method.method = a.method;
  method.width = width, method.height = height, method.seed = a.seed, method.num_threads = a.threads;
  method.roller = a.roller;
  method.quilt = a.quilt;
  method.block = a.block;
  method.block.search = a.brute_force ? BlockSearch::kBruteForce : BlockSearch::kRejection;
  if (a.block_basis != "principal" && a.block_basis != "walsh")
    return Fail(verb, "--bound-basis must be principal or walsh, not '" + a.block_basis + "'", kExitUsage);
  method.block.basis = a.block_basis == "walsh" ? BlockBasis::kWalshHadamard : BlockBasis::kPrincipal;
  method.texton_analysis = a.texton_analysis;
  method.texton = a.texton;
  method.texton.search = a.brute_force ? TextonSearch::kFull : TextonSearch::kCoherence;
  method.textons = a.analysis;
  if (a.method == "texton") {
    if (Status st = method.texton_analysis.Check(); !st.ok()) return Fail(verb, st.message(), kExitUsage);
    if (Status st = method.texton.Check(); !st.ok()) return Fail(verb, st.message(), kExitUsage);
  }
  method.svd_components = a.exemplar.svd_components;
  Json report;
  std::string note;
  ProgressBar bar(a.method == "quilt" ? "quilting" : a.method, !a.no_progress);
  TextonAnalysis textons;
  auto map = RunSynthesisMethod(*e, method, &report, &note, bar.AsCallback(), &textons);
  if (!map.ok())
    return Fail(verb, a.input.string() + ": " + map.status().message(),
                map.status().message() == "cancelled" ? kExitCancelled : kExitFailure);
  if (!note.empty()) std::fprintf(stderr, "mesocap synth: %s: %s\n", a.input.string().c_str(), note.c_str());
  // A texton analysis is kept beside the map, so a later run (or a surface) reuses it with --analysis.
  return Finish(verb, *map, *e, a, report, TextonAnalysisWriter(textons));
}

int RunApply(SynthArgs& a) {
  const std::string verb = "synth-apply";
  if (int code = CheckCommon(verb, a, nullptr, nullptr)) return code;
  auto map = ReadSynthMap(a.map);
  if (!map.ok()) return Fail(verb, map.status().message());
  a.exemplar.svd_components = 1;  // the map is given: features only feed the report
  auto e = Load(a, verb);
  if (!e.ok()) return Fail(verb, e.status().message());
  if (e->width != map->sample_width || e->height != map->sample_height)
    return Fail(verb, a.map.string() + ": points into a " + std::to_string(map->sample_width) + "x" +
                          std::to_string(map->sample_height) + " sample; " + a.input.string() + " is " +
                          std::to_string(e->width) + "x" + std::to_string(e->height));
  return Finish(verb, *map, *e, a, {{"method", map->method}, {"map", a.map.string()}});
}

int RunPaint(SynthArgs& a) {
  const std::string verb = "paint";
  int width = 0, height = 0;
  if (int code = CheckCommon(verb, a, &width, &height)) return code;
  auto feature = ReadMask(a.feature_mask);
  if (!feature.ok()) return Fail(verb, feature.status().message());
  auto target = ReadMask(a.target_mask);
  if (!target.ok()) return Fail(verb, target.status().message());
  auto e = Load(a, verb);
  if (!e.ok()) return Fail(verb, e.status().message());
  if (feature->width() != e->width || feature->height() != e->height)
    return Fail(verb, a.feature_mask.string() + ": " + std::to_string(feature->width()) + "x" + std::to_string(feature->height()) +
                          ", the sample is " + std::to_string(e->width) + "x" + std::to_string(e->height));
  if (target->width() != width || target->height() != height)
    return Fail(verb, a.target_mask.string() + ": " + std::to_string(target->width()) + "x" + std::to_string(target->height()) +
                          ", --size is " + std::to_string(width) + "x" + std::to_string(height));
  QuiltOptions o = a.quilt;
  o.width = width, o.height = height, o.seed = a.seed, o.num_threads = a.threads;
  QuiltReport r;
  ProgressBar bar("painting", !a.no_progress);
  auto map = PaintSynthesis(e->features, *feature, *target, o, a.paint, &r, bar.AsCallback());
  if (!map.ok()) return Fail(verb, a.input.string() + ": " + map.status().message());
  Json report = {{"method", "paint"}};
  report["parameters"] = {{"transition_width", a.paint.transition_width}, {"match_weight", a.paint.match_weight},
                          {"data_weight", a.paint.data_weight}, {"verbatim", a.paint.verbatim}, {"seed", a.seed},
                          {"width", width}, {"height", height}, {"feature_mask", a.feature_mask.string()},
                          {"target_mask", a.target_mask.string()}};
  report["patches"] = r.patches;
  report["repair_patches"] = r.repair_patches;
  report["seconds_synthesis"] = r.seconds;
  return Finish(verb, *map, *e, a, report);
}

void AddCommonOptions(CLI::App* sub, SynthArgs& a, bool needs_size) {
  sub->add_option("--input", a.input, "Exemplar: an image, a BTF folder or index.json, a session (its slices), or a .ptm")
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
  sub->add_option("--svd-components", a.exemplar.svd_components, "BTF: geometry maps kept from the SVD (Zhou: 40)")->capture_default_str();
}

void AddTextonOptions(CLI::App* sub, SynthArgs& a) {
  sub->add_option("--k", a.texton.k, "texton: k of the k-coherence search (Tong: 11; 1 is Ashikhmin's method)")->capture_default_str();
  sub->add_option("--neighbourhood", a.texton.neighbourhood, "texton: N, the N x N neighbourhood at a texel's level")
      ->capture_default_str();
  sub->add_option("--parent-neighbourhood", a.texton.parent_neighbourhood, "texton: P x P neighbourhood at the level above")
      ->capture_default_str();
  sub->add_option("--passes", a.texton.passes, "texton: resynthesis passes per level (Tong: 1)")->capture_default_str();
  sub->add_option("--textons", a.texton_analysis.textons, "texton: n_t, textons at the finest level (a quarter per level above)")
      ->capture_default_str();
  sub->add_option("--representative-slices", a.texton_analysis.representative_slices,
                  "texton: n_s, slices chosen by K-means whose filter responses are clustered")
      ->capture_default_str();
  sub->add_option("--levels", a.texton_analysis.levels, "texton: pyramid levels")->capture_default_str();
  sub->add_option("--texton-dimensions", a.texton_analysis.dimensions,
                  "texton: principal directions kept of the concatenated filter responses")
      ->capture_default_str();
  sub->add_option("--analysis", a.analysis, "texton: reuse a saved analysis (textons.exr of an earlier run on this exemplar)");
  sub->add_option("--audit", a.texton.audit_fraction,
                  "texton: share of queries also answered by the full search (reports how often both agree)")
      ->capture_default_str();
}

}  // namespace

Command SynthCommand() {
  auto args = std::make_shared<SynthArgs>();
  Command c;
  c.name = "synth";
  c.setup = [args](CLI::App& app) {
    CLI::App* sub = app.add_subcommand(
        "synth", "Enlarge a material: a texture-coordinate map by the BTF roller, graphcut quilting, block synthesis (ptm-block) "
                 "or 3D textons with k-coherence search (texton)");
    sub->add_option("--method", args->method, "roller, quilt, ptm-block or texton")->capture_default_str();
    AddCommonOptions(sub, *args, true);
    AddQuiltOptions(sub, *args);
    sub->add_option("--tiles", args->roller.tiles, "Roller: tiles with identical borders")->capture_default_str();
    sub->add_option("--block", args->block.block, "ptm-block: block side in texels (the paper: 30)")->capture_default_str();
    sub->add_option("--overlap", args->block.overlap, "ptm-block: overlap of neighbouring blocks (0: block / 6)")->capture_default_str();
    sub->add_option("--tolerance", args->block.tolerance,
                    "ptm-block: blocks within (1 + tolerance) of the best neighbourhood distance are drawn from at random")
        ->capture_default_str();
    sub->add_option("--projections", args->block.projections, "ptm-block: basis vectors of the rejection search's lower bounds")
        ->capture_default_str();
    sub->add_flag("--brute-force", args->brute_force,
                  "ptm-block: compute every candidate's distance (same result, slower); texton: the full search");
    sub->add_option("--bound-basis", args->block_basis,
                    "ptm-block: basis of the lower bounds: principal (the neighbourhoods' SVD) or walsh (Walsh-Hadamard)")
        ->capture_default_str();
    AddTextonOptions(sub, *args);
  };
  c.run = [args]() { return RunSynth(*args); };
  return c;
}

Command SynthApplyCommand() {
  auto args = std::make_shared<SynthArgs>();
  Command c;
  c.name = "synth-apply";
  c.setup = [args](CLI::App& app) {
    CLI::App* sub = app.add_subcommand("synth-apply", "Apply a synthesis map to another exemplar of the same sample");
    sub->add_option("--map", args->map, "map.exr written by synth or paint")->required();
    AddCommonOptions(sub, *args, false);
  };
  c.run = [args]() { return RunApply(*args); };
  return c;
}

Command PaintCommand() {
  auto args = std::make_shared<SynthArgs>();
  Command c;
  c.name = "paint";
  c.setup = [args](CLI::App& app) {
    CLI::App* sub = app.add_subcommand("paint", "Graphcut texture painting: put the sample's feature where a target mask says");
    AddCommonOptions(sub, *args, true);
    AddQuiltOptions(sub, *args);
    sub->add_option("--feature-mask", args->feature_mask, "Sample-size mask, white = the feature")->required();
    sub->add_option("--target-mask", args->target_mask, "Output-size mask, white = where the feature goes")->required();
    sub->add_option("--transition", args->paint.transition_width, "Width of m0's linear transition zone (texels)")->capture_default_str();
    sub->add_flag("--verbatim", args->paint.verbatim, "Copy the whole feature once instead of synthesizing it");
  };
  c.run = [args]() { return RunPaint(*args); };
  return c;
}

}  // namespace mesocap::app
