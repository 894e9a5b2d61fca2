#include "reconstruct/btf_evaluation.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <sstream>

#include "core/cancel.h"
#include "core/directions.h"
#include "core/median.h"
#include "core/parallel.h"
#include "core/progress.h"
#include "core/text_format.h"
#include "reconstruct/colour.h"

namespace mesocap {
namespace {

double RmsDifference(const Image& a, const Image& b) {
  double sum = 0;
  for (size_t i = 0; i < a.size(); ++i) sum += double(a.data()[i] - b.data()[i]) * (a.data()[i] - b.data()[i]);
  return std::sqrt(sum / double(a.size()));
}

bool NearAny(const Eigen::Vector3d& d, const std::vector<Eigen::Vector3d>& set, double tol_deg) {
  return std::any_of(set.begin(), set.end(), [&](const Eigen::Vector3d& s) { return AngleBetweenDeg(d, s) < tol_deg; });
}

Json PairJson(const Eigen::Vector3d& light, const Eigen::Vector3d& view) {
  const Eigen::Vector2d i = AnglesDegFromDirection(light), o = AnglesDegFromDirection(view);
  return {{"theta_i_deg", i.x()}, {"phi_i_deg", i.y()}, {"theta_o_deg", o.x()}, {"phi_o_deg", o.y()}};
}

// `image` with each channel scaled to the mean of that channel in `reference`.
Image ScaledToMeansOf(Image image, const Image& reference) {
  const std::vector<double> want = ChannelMeans(reference), have = ChannelMeans(image);
  for (size_t i = 0; i < image.pixel_count(); ++i)
    for (int c = 0; c < image.channels(); ++c)
      image.data()[i * image.channels() + c] *= have[c] > 0 ? float(want[c] / have[c]) : 0.0f;
  return image;
}

}  // namespace

std::string BtfMethodToString(BtfMethod method) {
  switch (method) {
    case BtfMethod::kStatistical: return "statistical";
    case BtfMethod::kTopView: return "top_view";
    case BtfMethod::kBrdfModulated: return "brdf_modulated";
  }
  return "unknown";
}

bool BtfEvaluationOptions::Check() const { return btf.Check() && held_out_tolerance_deg >= 0 && max_pairs != 0; }

std::vector<Eigen::Vector3d> RigViewDirections() {
  std::vector<Eigen::Vector3d> views = {Eigen::Vector3d::UnitZ()};
  for (int k = 0; k < 4; ++k) views.push_back(DirectionFromAnglesDeg(30, 90.0 * k));
  for (int k = 0; k < 8; ++k) views.push_back(DirectionFromAnglesDeg(60, 45.0 * k));
  return views;
}

std::array<Image, kBtfMethods> ReconstructAllMethods(const StatisticalBtf& btf, const Eigen::Vector3d& light,
                                                     const Eigen::Vector3d& view, const Image& truth) {
  std::array<Image, kBtfMethods> out;
  out[int(BtfMethod::kStatistical)] = btf.Reconstruct(light, view);
  out[int(BtfMethod::kTopView)] = btf.BaseTexture(light);
  // One texture (top view, top light) scaled per channel to the pair's true average BRDF.
  out[int(BtfMethod::kBrdfModulated)] = ScaledToMeansOf(btf.BaseTexture(Eigen::Vector3d::UnitZ()), truth);
  return out;
}

PairScore ScoreMethods(const std::array<Image, kBtfMethods>& methods, const Image& truth,
                       const SliceStatisticsOptions& options) {
  const SliceStatistics truth_stats = ComputeSliceStatistics(truth, options);
  const double truth_saturation = SaturationQuantile(truth, 0.95);
  PairScore score;
  for (int m = 0; m < kBtfMethods; ++m) {
    score.rmse[m] = RmsDifference(methods[m], truth);
    const SliceStatistics stats = ComputeSliceStatistics(methods[m], options);
    double wp = 0, wb = 0;
    for (int c = 0; c < stats.channels; ++c) {
      wp += WassersteinDistance(stats.pixels[c], truth_stats.pixels[c]) / stats.channels;
      for (int b = 0; b < stats.band_count; ++b)
        wb += WassersteinDistance(stats.band(c, b), truth_stats.band(c, b)) / (stats.channels * stats.band_count);
    }
    score.wasserstein_pixels[m] = wp;
    score.wasserstein_bands[m] = wb;
    score.wasserstein_chromaticity[m] = ChromaticityDistance(methods[m], truth);
    score.saturation_ratio[m] = truth_saturation > 0 ? SaturationQuantile(methods[m], 0.95) / truth_saturation : 1.0;
  }
  return score;
}

std::string LightCoverageToString(LightCoverage coverage) {
  switch (coverage) {
    case LightCoverage::kInside: return "inside";
    case LightCoverage::kNear: return "near";
    case LightCoverage::kFar: return "far";
  }
  return "unknown";
}

double BtfEvaluation::FractionBeatingBoth(MethodScores score, std::optional<LightCoverage> coverage) const {
  int wins = 0, count = 0;
  for (const PairScore& p : pairs) {
    if (coverage && p.coverage != *coverage) continue;
    const auto& w = p.*score;
    wins += w[0] < w[1] && w[0] < w[2];
    ++count;
  }
  return count ? double(wins) / double(count) : 0.0;
}

int BtfEvaluation::CountWith(LightCoverage coverage) const {
  return int(std::count_if(pairs.begin(), pairs.end(), [&](const PairScore& p) { return p.coverage == coverage; }));
}

namespace {

std::vector<double> SaturationErrors(const std::vector<PairScore>& pairs, int method) {
  std::vector<double> v;
  for (const PairScore& p : pairs) v.push_back(std::abs(p.saturation_ratio[method] - 1));
  return v;
}

}  // namespace

std::array<double, kBtfMethods> BtfEvaluation::Median(MethodScores score) const {
  std::array<double, kBtfMethods> median{};
  for (int m = 0; m < kBtfMethods; ++m) {
    std::vector<double> v;
    for (const PairScore& p : pairs) v.push_back((p.*score)[m]);
    median[m] = UpperMedian(std::move(v));
  }
  return median;
}

std::array<double, kBtfMethods> BtfEvaluation::MedianSaturationError() const {
  std::array<double, kBtfMethods> out{};
  for (int m = 0; m < kBtfMethods; ++m) out[m] = UpperMedian(SaturationErrors(pairs, m));
  return out;
}

std::array<double, kBtfMethods> BtfEvaluation::WorstSaturationError() const {
  std::array<double, kBtfMethods> out{};
  for (int m = 0; m < kBtfMethods; ++m) {
    const std::vector<double> v = SaturationErrors(pairs, m);
    out[m] = v.empty() ? 0 : *std::max_element(v.begin(), v.end());
  }
  return out;
}

Json BtfEvaluation::ToJson() const {
  Json summary;
  for (int m = 0; m < kBtfMethods; ++m) {
    const std::string name = BtfMethodToString(BtfMethod(m));
    summary[name] = {{"median_rmse", Median(&PairScore::rmse)[m]},
                     {"median_wasserstein_pixels", Median(&PairScore::wasserstein_pixels)[m]},
                     {"median_wasserstein_bands", Median(&PairScore::wasserstein_bands)[m]},
                     {"median_wasserstein_chromaticity", Median(&PairScore::wasserstein_chromaticity)[m]},
                     {"median_saturation_error", MedianSaturationError()[m]},
                     {"worst_saturation_error", WorstSaturationError()[m]}};
  }
  Json j = {{"held_out_pairs", pairs.size()},
            {"held_out_pairs_total", held_out_total},
            {"input_slices", input_slices},
            {"fraction_beating_both_wasserstein_pixels", FractionBeatingBoth(&PairScore::wasserstein_pixels)},
            {"fraction_beating_both_wasserstein_bands", FractionBeatingBoth(&PairScore::wasserstein_bands)},
            {"fraction_beating_both_wasserstein_chromaticity", FractionBeatingBoth(&PairScore::wasserstein_chromaticity)},
            {"methods", summary},
            {"seconds_inputs", seconds_inputs},
            {"seconds_statistics", seconds_statistics},
            {"seconds_scoring", seconds_scoring},
            {"reconstruct_ms_per_slice", reconstruct_ms_per_slice}};
  for (const LightCoverage c : {LightCoverage::kInside, LightCoverage::kNear, LightCoverage::kFar})
    j["by_light_coverage"][LightCoverageToString(c)] = {
        {"pairs", CountWith(c)}, {"fraction_beating_both_wasserstein_pixels", FractionBeatingBoth(&PairScore::wasserstein_pixels, c)}};
  Json list = Json::array();
  for (const PairScore& p : pairs) {
    Json e = PairJson(p.light, p.view);
    e["light_coverage"] = LightCoverageToString(p.coverage);
    for (int m = 0; m < kBtfMethods; ++m)
      e[BtfMethodToString(BtfMethod(m))] = {{"rmse", p.rmse[m]}, {"w_pixels", p.wasserstein_pixels[m]},
                                            {"w_bands", p.wasserstein_bands[m]},
                                            {"w_chromaticity", p.wasserstein_chromaticity[m]},
                                            {"saturation_ratio", p.saturation_ratio[m]}};
    list.push_back(e);
  }
  j["pairs"] = list;
  return j;
}

std::string BtfEvaluation::Brief() const {
  const auto w = Median(&PairScore::wasserstein_pixels);
  std::string by_coverage;
  for (const LightCoverage c : {LightCoverage::kInside, LightCoverage::kNear, LightCoverage::kFar})
    if (CountWith(c) > 0)
      by_coverage += Format("%s%s %.0f%% of %d", by_coverage.empty() ? "" : ", ", LightCoverageToString(c).c_str(),
                            100.0 * FractionBeatingBoth(&PairScore::wasserstein_pixels, c), CountWith(c));
  const bool sampled = int(pairs.size()) < held_out_total;
  const std::string scored = sampled ? Format("%zu of %d held-out pairs (spread over views and lights)", pairs.size(),
                                              held_out_total)
                                     : Format("%zu held-out pairs", pairs.size());
  return Format("%s; statistical beats both baselines on pixel Wasserstein in %.0f%% (by the pair's "
                "light against the views' measured lights: %s; subbands %.0f%%, chromaticity %.0f%%); median W1 "
                "statistical %.5f, top view %.5f, BRDF-modulated %.5f; 95th-percentile saturation within %.1f%% of the "
                "truth's at the median, %.1f%% at worst",
                scored.c_str(), 100.0 * FractionBeatingBoth(&PairScore::wasserstein_pixels), by_coverage.c_str(),
                100.0 * FractionBeatingBoth(&PairScore::wasserstein_bands),
                100.0 * FractionBeatingBoth(&PairScore::wasserstein_chromaticity), w[0], w[1], w[2],
                100.0 * MedianSaturationError()[0], 100.0 * WorstSaturationError()[0]);
}

StatusOr<BtfEvaluation> EvaluateStatisticalBtf(const TrueSliceFn& truth, const BtfEvaluationOptions& options_in,
                                               const ProgressFn& progress, std::optional<StatisticalBtf>* model) {
  if (!options_in.Check()) return Status::Error("invalid evaluation options");
  BtfEvaluationOptions options = options_in;
  if (options.input_views.empty()) options.input_views = RigViewDirections();
  if (options.input_lights.empty()) options.input_lights = BonnDirections();
  const int num_threads = options.btf.num_threads;

  // 1. The measured data: every input view under each of its lights.
  auto start = std::chrono::steady_clock::now();
  const int views = int(options.input_views.size());
  if (options.input_lights_by_view.empty()) options.input_lights_by_view.assign(views, options.input_lights);
  if (int(options.input_lights_by_view.size()) != views) return Status::Error("one list of input lights per input view");
  std::vector<std::pair<int, int>> inputs;  // (view, light)
  for (int v = 0; v < views; ++v)
    for (int l = 0; l < int(options.input_lights_by_view[v].size()); ++l) inputs.push_back({v, l});
  std::vector<std::vector<Image>> slices(views);
  for (int v = 0; v < views; ++v) slices[v].resize(options.input_lights_by_view[v].size());
  std::atomic<int> done = 0;
  std::atomic<bool> cancelled = false;
  ParallelFor(0, int(inputs.size()), [&](int k) {
    if (cancelled) return;
    const auto [v, l] = inputs[k];
    slices[v][l] = truth(options.input_lights_by_view[v][l], options.input_views[v]);
    if (!ReportProgress(progress, ++done, int(inputs.size()), "render inputs")) cancelled = true;
  }, num_threads);
  if (cancelled) return Status::Cancelled();
  const int input_slices = int(inputs.size());
  const double seconds_inputs = SecondsSince(start);

  // 2. Statistics of every input slice; the top view's slices are the base textures.
  start = std::chrono::steady_clock::now();
  int top = 0;
  for (int v = 1; v < views; ++v)
    if (options.input_views[v].normalized().z() > options.input_views[top].normalized().z()) top = v;
  options.btf = WithColourChannels(options.btf, slices[top]);
  std::vector<MeasuredView> measured;
  for (int v = 0; v < views; ++v) {
    if (CancelRequested()) return Status::Cancelled();
    measured.push_back(MeasureView(options.input_views[v], options.input_lights_by_view[v], slices[v], options.btf));
  }
  auto btf = StatisticalBtf::Create(std::move(slices[top]), options.input_lights_by_view[top], std::move(measured), options.btf);
  if (!btf.ok()) return btf.status();
  slices.clear();
  const double seconds_statistics = SecondsSince(start);

  // 3. Held-out pairs: target views that are not input views, under every target light.
  auto scored = ScoreHeldOutPairs(*btf, truth, options, progress);
  if (!scored.ok()) return scored.status();
  scored->input_slices = input_slices;
  scored->seconds_inputs = seconds_inputs;
  scored->seconds_statistics = seconds_statistics;
  if (model) *model = std::move(*btf);
  return scored;
}

std::vector<std::pair<int, int>> SpreadPairSample(int views, int lights, int max_pairs) {
  std::vector<std::pair<int, int>> pairs;
  if (max_pairs < 0 || int64_t(views) * lights <= max_pairs) {
    for (int v = 0; v < views; ++v)
      for (int l = 0; l < lights; ++l) pairs.push_back({v, l});
    return pairs;
  }
  // Views in order, each as often as the count allows; lights by the golden-ratio sequence, whose
  // terms fill the lights evenly and independently of the views (a light a view already has moves
  // on to the next free one). A stride through the view-major list instead aliases with the light
  // count: 80 views x 81 lights in 240 steps of 27 lights gave every view the same 3 lights.
  constexpr double kGoldenFraction = 0.6180339887498949;
  std::vector<char> taken(size_t(lights), 0);
  for (int k = 0; k < max_pairs; ++k) {
    const int view = int(int64_t(k) * views / max_pairs);
    if (k > 0 && view != pairs.back().first) std::fill(taken.begin(), taken.end(), 0);
    int light = std::min(lights - 1, int(std::fmod(0.5 + k * kGoldenFraction, 1.0) * lights));
    while (taken[size_t(light)]) light = (light + 1) % lights;
    taken[size_t(light)] = 1;
    pairs.push_back({view, light});
  }
  return pairs;
}

StatusOr<BtfEvaluation> ScoreHeldOutPairs(const StatisticalBtf& btf, const TrueSliceFn& truth,
                                          const BtfEvaluationOptions& options, const ProgressFn& progress) {
  std::vector<Eigen::Vector3d> input_views;
  for (const MeasuredView& v : btf.views()) input_views.push_back(v.view);
  const std::vector<Eigen::Vector3d> target_views = options.target_views.empty() ? BonnDirections() : options.target_views;
  const std::vector<Eigen::Vector3d> target_lights = options.target_lights.empty() ? BonnDirections() : options.target_lights;
  std::vector<Eigen::Vector3d> held_out_views;
  for (const auto& view : target_views)
    if (!NearAny(view, input_views, options.held_out_tolerance_deg)) held_out_views.push_back(view);
  if (held_out_views.empty()) return Status::Error("no held-out pairs: every target view is an input view");
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> held_out;  // (light, view)
  for (const auto& [v, l] : SpreadPairSample(int(held_out_views.size()), int(target_lights.size()), options.max_pairs))
    held_out.push_back({target_lights[size_t(l)], held_out_views[size_t(v)]});

  BtfEvaluation eval;
  eval.held_out_total = int(held_out_views.size() * target_lights.size());
  const auto start = std::chrono::steady_clock::now();
  eval.pairs.resize(held_out.size());
  std::atomic<long long> reconstruct_ns = 0;
  std::atomic<int> done = 0;
  std::atomic<bool> cancelled = false;
  ParallelFor(0, int(held_out.size()), [&](int k) {
    if (cancelled) return;
    const auto& [light, view] = held_out[k];
    const Image truth_slice = truth(light, view);
    const auto t0 = std::chrono::steady_clock::now();
    std::array<Image, kBtfMethods> result = ReconstructAllMethods(btf, light, view, truth_slice);
    if (options.statistical_at_true_mean) result[0] = ScaledToMeansOf(std::move(result[0]), truth_slice);
    reconstruct_ns += std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - t0).count();
    PairScore& score = eval.pairs[k];
    score = ScoreMethods(result, truth_slice, options.btf.statistics);
    score.light = light, score.view = view;
    score.coverage = btf.LightCovered(light, view)                ? LightCoverage::kInside
                     : btf.LightGapDeg(light, view) <= kNearHullDeg ? LightCoverage::kNear
                                                                    : LightCoverage::kFar;
    if (!ReportProgress(progress, ++done, int(held_out.size()), "score held-out pairs")) cancelled = true;
  }, options.btf.num_threads);
  if (cancelled) return Status::Cancelled();
  eval.seconds_scoring = SecondsSince(start);
  eval.reconstruct_ms_per_slice = 1e-6 * double(reconstruct_ns) / double(held_out.size());
  return eval;
}

}  // namespace mesocap
