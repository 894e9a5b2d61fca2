#include "app/synth_run.h"

#include <chrono>

namespace mesocap::app {

bool IsSynthMethod(const std::string& name) { return name == "roller" || name == "quilt" || name == "ptm-block"; }

std::string SynthMethodOptions::Check() const {
  if (!IsSynthMethod(method)) return "unknown method '" + method + "' (roller, quilt, ptm-block)";
  if (width < 1 || height < 1 || width > 32768 || height > 32768) return "the output size must be 1..32768 a side";
  return "";
}

namespace {

// A method's options with the output size, seed and threads every method takes from `a`.
template <typename MethodOptions>
MethodOptions WithCommon(MethodOptions o, const SynthMethodOptions& a) {
  o.width = a.width, o.height = a.height, o.seed = a.seed, o.num_threads = a.num_threads;
  return o;
}

StatusOr<SynthMap> RunRoller(const Exemplar& e, const SynthMethodOptions& a, Json* report, std::string* note) {
  const RollerOptions o = WithCommon(a.roller, a);
  Image luminance(e.width, e.height, 1);
  for (size_t t = 0; t < luminance.pixel_count(); ++t)
    luminance.data()[t] = 0.2126f * e.preview.data()[3 * t] + 0.7152f * e.preview.data()[3 * t + 1] + 0.0722f * e.preview.data()[3 * t + 2];
  RollerReport r;
  auto map = RollerSynthesis(e.features, luminance, o, &r);
  if (!map.ok()) return map.status();
  if (r.frequency_fallback && note) *note = r.fallback_reason;
  (*report)["parameters"] = {{"tiles", o.tiles}, {"alpha", o.alpha}, {"interior_alpha", o.interior_alpha}, {"seed", o.seed},
                             {"width", o.width}, {"height", o.height}, {"svd_components", a.svd_components}};
  Json interiors = Json::array();
  for (const auto& p : r.interior_sources) interiors.push_back({p.x(), p.y()});
  (*report)["derived"] = {{"frequency_rows", r.frequency_rows}, {"frequency_columns", r.frequency_columns},
                          {"frequency_fallback", r.frequency_fallback}, {"fallback_reason", r.fallback_reason},
                          {"overlap_rows", r.overlap_rows}, {"overlap_columns", r.overlap_columns},
                          {"tile_width", r.tile_width}, {"tile_height", r.tile_height},
                          {"rectangle", {r.rectangle_x, r.rectangle_y}}, {"vertex", {r.vertex_row, r.vertex_column}},
                          {"mean_cut_error", r.mean_cut_error}, {"interior_sources", interiors}};
  (*report)["seconds_analysis"] = r.seconds_analysis;
  (*report)["seconds_synthesis"] = r.seconds_synthesis;
  return map;
}

StatusOr<SynthMap> RunBlocks(const Exemplar& e, const SynthMethodOptions& a, Json* report, const ProgressFn& progress) {
  const BlockSynthesisOptions o = WithCommon(a.block, a);
  BlockSynthesisReport r;
  auto map = BlockSynthesis(e.features, o, &r, progress);
  if (!map.ok()) return map.status();
  (*report)["parameters"] = {{"block", o.block}, {"overlap", r.overlap}, {"tolerance", o.tolerance},
                             {"projections", o.projections},
                             {"search", o.search == BlockSearch::kRejection ? "rejection" : "brute force"},
                             {"bound_basis", o.basis == BlockBasis::kPrincipal ? "principal directions" : "Walsh-Hadamard"},
                             {"features", e.kind == ExemplarKind::kPtm ? "Legendre coefficients per colour channel"
                                                                        : "the exemplar's features"},
                             {"seed", o.seed}, {"width", o.width}, {"height", o.height}};
  (*report)["blocks"] = r.blocks;
  (*report)["candidates_per_query"] = r.candidates_per_query;
  (*report)["full_distances"] = r.full_distances;
  (*report)["rejected_fraction"] = r.rejected_fraction;
  (*report)["mean_cut_error"] = r.mean_cut_error;
  (*report)["seconds_basis"] = r.seconds_basis;
  (*report)["seconds_search"] = r.seconds_search;
  (*report)["seconds_cutting"] = r.seconds_cut;
  (*report)["seconds_synthesis"] = r.seconds;
  return map;
}

StatusOr<SynthMap> RunQuilt(const Exemplar& e, const SynthMethodOptions& a, Json* report, const ProgressFn& progress) {
  const QuiltOptions o = WithCommon(a.quilt, a);
  QuiltReport r;
  auto map = QuiltSynthesis(e.features, o, &r, progress);
  if (!map.ok()) return map.status();
  (*report)["parameters"] = {{"patch_radius", o.patch_radius}, {"min_patch_radius", o.min_patch_radius}, {"shrink", o.shrink},
                             {"seam_threshold", o.seam_threshold}, {"randomness", o.randomness}, {"rotations", o.rotations},
                             {"seed", o.seed}, {"width", o.width}, {"height", o.height}, {"svd_components", a.svd_components}};
  (*report)["derived"] = {{"patch_radius", r.patch_radius}, {"sample_neighbour_step", r.sample_neighbour_step}};
  (*report)["patches"] = r.patches;
  (*report)["rejected_cuts"] = r.rejected_cuts;
  (*report)["mean_seam_cost"] = r.mean_seam_cost;
  (*report)["seconds_matching"] = r.seconds_matching;
  (*report)["seconds_cutting"] = r.seconds_cutting;
  (*report)["seconds_synthesis"] = r.seconds;
  return map;
}

}  // namespace

StatusOr<SynthMap> RunSynthesisMethod(const Exemplar& e, const SynthMethodOptions& a, Json* report_out, std::string* note,
                                      const ProgressFn& progress) {
  if (std::string why = a.Check(); !why.empty()) return Status::Error(why);
  const auto start = std::chrono::steady_clock::now();
  Json report = {{"method", a.method}};
  auto map = a.method == "roller"      ? RunRoller(e, a, &report, note)
             : a.method == "ptm-block" ? RunBlocks(e, a, &report, progress)
                                       : RunQuilt(e, a, &report, progress);
  if (!map.ok()) return map.status();
  report["seconds_total_method"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  *report_out = std::move(report);
  return map;
}

}  // namespace mesocap::app
