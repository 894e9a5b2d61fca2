// The validation of Ngan & Durand section 4 on any source of true slices: keep the rig's 13
// views (top, 4 at 30 deg, 8 at 60 deg) under all input lights, reconstruct every held-out
// (light, view) pair of a target grid, and score it against the truth next to the paper's two
// baselines: the top-view slice alone, and one top-view texture (lit from the top) scaled to
// the true average BRDF of the pair.
#pragma once

#include <array>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/image.h"
#include "core/json.h"
#include "core/progress.h"
#include "core/status.h"
#include "reconstruct/statistical_btf.h"

namespace mesocap {

// Renders the true slice for a (light, view) pair, patch frame, unit directions.
using TrueSliceFn = std::function<Image(const Eigen::Vector3d& light, const Eigen::Vector3d& view)>;

enum class BtfMethod { kStatistical = 0, kTopView = 1, kBrdfModulated = 2 };
inline constexpr int kBtfMethods = 3;
std::string BtfMethodToString(BtfMethod method);  // "statistical", "top_view", "brdf_modulated"

struct BtfEvaluationOptions {
  StatisticalBtfOptions btf;
  std::vector<Eigen::Vector3d> input_views;    // empty: RigViewDirections()
  std::vector<Eigen::Vector3d> input_lights;   // empty: BonnDirections()
  // When not empty, the lights of each input view instead (a capture session's sparse lights).
  std::vector<std::vector<Eigen::Vector3d>> input_lights_by_view;
  std::vector<Eigen::Vector3d> target_views;   // empty: BonnDirections()
  std::vector<Eigen::Vector3d> target_lights;  // empty: BonnDirections()
  // A target view within this angle of an input view is not held out.
  double held_out_tolerance_deg = 0.5;
  // Score at most this many held-out pairs, spread over views and lights (SpreadPairSample; -1: all).
  int max_pairs = -1;
  // A diagnostic, not a method: the statistical slice is scaled per channel to the truth's mean
  // before it is scored (the oracle the BRDF-modulated baseline has), to tell how much of its
  // error is in the mean radiance rather than in the shape of its distributions.
  bool statistical_at_true_mean = false;
  bool Check() const;
};

// Where a held-out pair's light lies against the lights the views it borrows from measured:
// inside their triangulated hull, near it (within kNearHullDeg of a measured light) or far outside.
enum class LightCoverage { kInside = 0, kNear = 1, kFar = 2 };
std::string LightCoverageToString(LightCoverage coverage);  // "inside", "near", "far"

struct PairScore {
  Eigen::Vector3d light, view;
  LightCoverage coverage = LightCoverage::kInside;
  // Per method (BtfMethod order), averaged over colour channels.
  std::array<double, kBtfMethods> rmse{}, wasserstein_pixels{}, wasserstein_bands{};
  // Colour (3-channel slices, reconstruct/colour.h): W1 of the chromaticity histograms, and the
  // 95th-percentile saturation over the truth's.
  std::array<double, kBtfMethods> wasserstein_chromaticity{}, saturation_ratio{};
};
using MethodScores = std::array<double, kBtfMethods> PairScore::*;

struct BtfEvaluation {
  std::vector<PairScore> pairs;
  int held_out_total = 0;  // held-out pairs before sampling (max_pairs): pairs is all of them or a spread sample
  int input_slices = 0;
  double seconds_inputs = 0, seconds_statistics = 0, seconds_scoring = 0;
  double reconstruct_ms_per_slice = 0;  // thread time per reconstructed slice
  // Share of pairs where the statistical reconstruction beats both baselines on a score (of the
  // pairs with that light coverage, when given).
  double FractionBeatingBoth(MethodScores score, std::optional<LightCoverage> coverage = std::nullopt) const;
  int CountWith(LightCoverage coverage) const;
  // Median of a score over pairs, per method.
  std::array<double, kBtfMethods> Median(MethodScores score) const;
  // Per method, the median and the largest over pairs of |saturation ratio - 1|.
  std::array<double, kBtfMethods> MedianSaturationError() const;
  std::array<double, kBtfMethods> WorstSaturationError() const;
  Json ToJson() const;
  std::string Brief() const;
};

// The rig's 13 views in the patch frame: top, 4 at 30 deg (phi 0, 90, 180, 270), 8 at 60 deg
// (phi every 45 deg).
std::vector<Eigen::Vector3d> RigViewDirections();

// Renders the inputs, builds the statistical BTF, scores the held-out pairs. `model`, when
// given, receives the reconstruction (for pictures). A view with too few or degenerate lights
// (input_lights_by_view) fails with a message.
StatusOr<BtfEvaluation> EvaluateStatisticalBtf(const TrueSliceFn& truth, const BtfEvaluationOptions& options,
                                               const ProgressFn& progress = nullptr, std::optional<StatisticalBtf>* model = nullptr);

// Which (view, light) index pairs of `views` x `lights` to score: all of them when max_pairs is
// -1 or not fewer; else max_pairs distinct pairs, the views evenly represented (in order) and the
// lights spread evenly over the list, independently of the views.
std::vector<std::pair<int, int>> SpreadPairSample(int views, int lights, int max_pairs);

// Scores a built reconstruction (from true slices above, or from a calibrated session's) on the
// held-out pairs: options.target_views not within held_out_tolerance_deg of a view `btf`
// measured, under every target light (at most max_pairs, by SpreadPairSample). Fills pairs and the
// scoring times; leaves the input figures to the caller.
StatusOr<BtfEvaluation> ScoreHeldOutPairs(const StatisticalBtf& btf, const TrueSliceFn& truth,
                                          const BtfEvaluationOptions& options, const ProgressFn& progress = nullptr);

// RMSE, pixel W1 and subband W1 of each method's slice against `truth`, averaged over colour
// channels (and subbands), and the colour scores; light and view are left for the caller.
PairScore ScoreMethods(const std::array<Image, kBtfMethods>& methods, const Image& truth,
                       const SliceStatisticsOptions& options = {});

// The three methods' slices for one pair: statistical, top view, BRDF-modulated (the last needs
// the truth's mean).
std::array<Image, kBtfMethods> ReconstructAllMethods(const StatisticalBtf& btf, const Eigen::Vector3d& light,
                                                     const Eigen::Vector3d& view, const Image& truth);

}  // namespace mesocap
