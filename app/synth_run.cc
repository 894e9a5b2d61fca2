#include "app/synth_run.h"

#include <chrono>

#include "core/session_layout.h"
#include "core/text_format.h"
#include "synth/filter_bank.h"

namespace mesocap::app {

bool IsSynthMethod(const std::string& name) {
  return name == "roller" || name == "quilt" || name == "ptm-block" || name == "texton";
}

std::string SynthMethodOptions::Check() const {
  if (!IsSynthMethod(method)) return "unknown method '" + method + "' (roller, quilt, ptm-block, texton)";
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
  const Image luminance = Luminance(e.preview);
  RollerReport r;
  auto map = RollerSynthesis(e.features, luminance, o, &r);
  if (!map.ok()) return map.status();
  if (r.frequency_fallback && note) *note = r.fallback_reason;
  if (r.tiles_made < o.tiles && note)
    *note += (note->empty() ? "" : "; ") + Format("made %d of the %d tiles asked: the sample has no room for another "
                                                  "distinct interior", r.tiles_made, o.tiles);
  (*report)["parameters"] = {{"tiles", o.tiles}, {"alpha", o.alpha}, {"interior_alpha", o.interior_alpha}, {"seed", o.seed},
                             {"width", o.width}, {"height", o.height}, {"svd_components", a.svd_components}};
  Json interiors = Json::array();
  for (const auto& p : r.interior_sources) interiors.push_back({p.x(), p.y()});
  (*report)["derived"] = {{"frequency_rows", r.frequency_rows}, {"frequency_columns", r.frequency_columns},
                          {"frequency_fallback", r.frequency_fallback}, {"fallback_reason", r.fallback_reason},
                          {"overlap_rows", r.overlap_rows}, {"overlap_columns", r.overlap_columns},
                          {"tile_width", r.tile_width}, {"tile_height", r.tile_height}, {"tiles_made", r.tiles_made},
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
                             {"seam_limit", o.seam_limit}, {"balance_usage", o.balance_usage}, {"projections", o.projections},
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
                             {"whole_sample", o.whole_sample}, {"usage_weight", o.usage_weight},
                             {"usage_tolerance", o.usage_tolerance},
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

// The analysis saved at `a.textons`, or a fresh one of the exemplar; a saved one must match the
// exemplar's size.
StatusOr<TextonAnalysis> TextonsFor(const Exemplar& e, const SynthMethodOptions& a, const ProgressFn& progress) {
  if (!a.textons.empty()) {
    auto saved = ReadTextonAnalysis(a.textons);
    if (!saved.ok()) return saved.status();
    if (saved->levels[0].width != e.width || saved->levels[0].height != e.height)
      return Status::Error(a.textons.string() + ": analyses a " + std::to_string(saved->levels[0].width) + "x" +
                           std::to_string(saved->levels[0].height) + " sample; the exemplar is " + std::to_string(e.width) +
                           "x" + std::to_string(e.height));
    return saved;
  }
  TextonAnalysisOptions o = a.texton_analysis;
  o.seed = a.seed, o.num_threads = a.num_threads;
  return AnalyzeTextons(AppearanceImageCount(e), [&](int k) { return AppearanceLuminance(e, k); }, o, progress);
}

StatusOr<SynthMap> RunTextons(const Exemplar& e, const SynthMethodOptions& a, Json* report, std::string* note,
                              const ProgressFn& progress, TextonAnalysis* analysis_out) {
  MESOCAP_RETURN_IF_ERROR(a.texton.CheckSample(e.width, e.height));  // said before the analysis, not after it
  auto analysis = TextonsFor(e, a, progress);
  if (!analysis.ok()) return analysis.status();
  const TextonSynthesisOptions o = WithCommon(a.texton, a);
  TextonSynthesisReport r;
  auto map = TextonSynthesis(*analysis, o, &r, progress);
  if (!map.ok()) return map.status();
  const TextonAnalysisOptions& ao = a.texton_analysis;
  const TextonLevel& finest = analysis->levels[0];
  if (a.textons.empty() && finest.textons < ao.textons && note)
    *note = "n_t = " + std::to_string(ao.textons) + " is more than the sample's texels allow: " + std::to_string(finest.textons) +
            " textons";
  (*report)["parameters"] = {{"k", o.k}, {"neighbourhood", o.neighbourhood}, {"passes", o.passes}, {"jitter", o.jitter},
                             {"search", o.search == TextonSearch::kCoherence ? "k-coherence" : "full"},
                             {"filters", kFilterBankSize}, {"representative_slices", ao.representative_slices},
                             {"textons", ao.textons}, {"levels", ao.levels}, {"dimensions", ao.dimensions},
                             {"audit_fraction", o.audit_fraction}, {"saved_analysis", a.textons.string()},
                             {"seed", o.seed}, {"width", o.width}, {"height", o.height}};
  Json levels = Json::array();
  for (size_t l = 0; l < analysis->levels.size(); ++l) {
    const TextonLevel& level = analysis->levels[l];
    Json entry = {{"width", level.width}, {"height", level.height}, {"spacing", level.spacing}, {"textons", level.textons},
                  {"energy_kept", level.energy_kept}};
    if (l < r.per_level.size()) {
      const TextonLevelReport& s = r.per_level[l];
      entry["queries"] = s.queries, entry["mean_candidates"] = s.mean_candidates;
      if (s.audited) entry["audited"] = s.audited, entry["full_search_agreement"] = s.full_search_agreement;
    }
    levels.push_back(entry);
  }
  (*report)["derived"] = {{"representative_slices", analysis->representative_slices}, {"slices", analysis->slice_count},
                          {"levels", levels}};
  if (r.audited) (*report)["full_search_agreement"] = r.full_search_agreement;
  (*report)["seconds_analysis"] = analysis->seconds;
  (*report)["seconds_neighbour_lists"] = r.seconds_neighbours;
  (*report)["seconds_synthesis"] = r.seconds_synthesis;
  if (analysis_out) *analysis_out = std::move(*analysis);
  return map;
}

}  // namespace

std::function<Status(const std::filesystem::path&)> TextonAnalysisWriter(const TextonAnalysis& analysis) {
  if (analysis.levels.empty()) return nullptr;
  return [&analysis](const std::filesystem::path& folder) { return WriteTextonAnalysis(SynthFolder{folder}.textons(), analysis); };
}

StatusOr<SynthMap> RunSynthesisMethod(const Exemplar& e, const SynthMethodOptions& a, Json* report_out, std::string* note,
                                      const ProgressFn& progress, TextonAnalysis* analysis) {
  if (std::string why = a.Check(); !why.empty()) return Status::Error(why);
  const auto start = std::chrono::steady_clock::now();
  Json report = {{"method", a.method}};
  auto map = a.method == "roller"      ? RunRoller(e, a, &report, note)
             : a.method == "ptm-block" ? RunBlocks(e, a, &report, progress)
             : a.method == "texton"    ? RunTextons(e, a, &report, note, progress, analysis)
                                       : RunQuilt(e, a, &report, progress);
  if (!map.ok()) return map.status();
  report["seconds_total_method"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  *report_out = std::move(report);
  return map;
}

}  // namespace mesocap::app
