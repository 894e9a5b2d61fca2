// Texton synthesis speeds at the settings, one run, figures on stdout: texton analysis of
// the 81-slice weave (128 x 128; the paper: about 45 minutes for 64 x 64 on its machine), then a
// 512 x 512 texton map by the k-coherence search (k = 11) and by the full search at the same
// settings, with the ratio and how often the k-coherence search found the full search's best.
// Usage: bench_textons [WORK_DIR] [--skip-full]
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "bench/bench_exemplar.h"
#include "synth/exemplar.h"
#include "synth/texton_analysis.h"
#include "synth/texton_synthesis.h"

using namespace mesocap;

static double Since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

int main(int argc, char** argv) {
  const std::filesystem::path work = argc > 1 ? argv[1] : std::filesystem::temp_directory_path() / "mesocap_synth_bench";
  const bool skip_full = argc > 2 && std::strcmp(argv[2], "--skip-full") == 0;
  const auto folder = bench::Weave81(work);
  if (folder.empty()) return 1;
  ExemplarOptions eo;
  eo.svd_components = 1;  // the texton analysis reads the slices itself
  auto e = LoadExemplar(folder, eo);
  if (!e.ok()) return std::fprintf(stderr, "%s\n", e.status().message().c_str()), 1;

  auto t = std::chrono::steady_clock::now();
  auto analysis = AnalyzeTextons(AppearanceImageCount(*e), [&](int k) { return AppearanceLuminance(*e, k); }, {});
  if (!analysis.ok()) return std::fprintf(stderr, "%s\n", analysis.status().message().c_str()), 1;
  std::printf("texton analysis, 81 slices of 128x128 (n_b 48, n_s %zu, n_t %d, %zu levels): %.2f s (target 30 s)\n",
              analysis->representative_slices.size(), analysis->levels[0].textons, analysis->levels.size(), Since(t));

  TextonSynthesisOptions o;
  o.width = o.height = 512;
  TextonSynthesisReport k;
  if (!TextonSynthesis(*analysis, o, &k).ok()) return 1;
  std::printf("k-coherence synthesis 512x512 (k 11, N %d, %d passes, jitter %.2f): %.2f s = nearest lists %.2f s + search %.2f s "
              "(target 2 s); %.1f candidates per query at the finest level\n",
              o.neighbourhood, o.passes, o.jitter, k.seconds, k.seconds_neighbours, k.seconds_synthesis,
              k.per_level[0].mean_candidates);
  o.audit_fraction = 0.02;
  TextonSynthesisReport audit;
  if (!TextonSynthesis(*analysis, o, &audit).ok()) return 1;
  std::printf("  the same with 2%% of the queries also answered by the full search: k-coherence found its best on %.1f%% of "
              "%ld (finest level %.1f%%)\n",
              100 * audit.full_search_agreement, audit.audited, 100 * audit.per_level[0].full_search_agreement);
  if (skip_full) return 0;
  o.audit_fraction = 0;
  o.search = TextonSearch::kFull;
  TextonSynthesisReport full;
  if (!TextonSynthesis(*analysis, o, &full).ok()) return 1;
  std::printf("full search 512x512, same settings: %.1f s; k-coherence is %.0fx faster (%.0f candidates per query)\n",
              full.seconds, full.seconds / k.seconds, full.per_level[0].mean_candidates);
  return 0;
}
