// Entire-patch matching (Kwatra et al. 2003, as Zhou 2005 §III-B uses it): every placement of
// the sample (and of its rotated copies) under a work window is scored by the sum of squared
// feature differences over the window's already-synthesized texels, normalised by their count
// (the overlap area). The sums are cross-correlations, computed with FFTs (FFTW):
//   SSD(t) = sum_p M(p) |O(p)|^2 - 2 sum_p M(p) O(p).S(p + t) + sum_p M(p) |S(p + t)|^2.
// An optional constraint channel adds lambda * sum_p (m0(p) - ms(p + t))^2 / window area over the
// whole window (graphcut painting's joint search, Zhou §IV-A).
#pragma once

#include <functional>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "core/image.h"

namespace mesocap {

// A rotated copy of the sample: the largest centred square that stays inside the sample after
// turning it by `rotation_deg` (synth_map.h's convention), sampled at nearest texels.
struct RotatedSample {
  double rotation_deg = 0;
  int size_x = 0, size_y = 0;  // extent of the copy in texels
  Image features;              // size_x x size_y
  Image constraint;            // 1 channel, or empty
  // Sample texel coordinates (centre) of the copy's texel (u, v).
  Eigen::Vector2d SourceOf(int u, int v) const;
  // The sample texel the copy's texel (u, v) was taken from (nearest, clamped into the sample).
  Eigen::Vector2i SourceTexel(int u, int v) const;
  int sample_width = 0, sample_height = 0;
  Eigen::Vector2d origin;      // sample coordinate of the copy's texel (0, 0) centre
};

RotatedSample MakeRotatedSample(const Image& features, const Image& constraint, double rotation_deg);

// The window to match: features of the output under it, which texels are synthesized, and the
// target constraint m0 (painting) over the whole window.
struct MatchWindow {
  int width = 0, height = 0;
  const Image* features = nullptr;    // the output's features (whole output)
  const std::vector<uint8_t>* synthesized = nullptr;  // whole output, 1 = has a value
  const Image* target_constraint = nullptr;  // whole output, 1 channel, or null
  int x0 = 0, y0 = 0;                 // window origin in the output
  double constraint_scale = 1;        // multiplies the matcher's constraint weight for this window
  // With placements that may leave the copy (PatchMatcherOptions::max_window): the window texel
  // that must land on the copy (-1: the window's centre).
  int anchor_x = -1, anchor_y = -1;
};

struct MatchResult {
  int rotation = 0;      // index into the rotated copies
  int u = 0, v = 0;      // the copy's texel under the window's origin (negative: the window starts off the copy)
  double cost = 0;       // normalised SSD (+ constraint term)
  bool found = false;
};

struct PatchMatcherOptions {
  double constraint_weight = 0;  // lambda of the constraint term (0: no constraint term)
  int num_threads = -1;
  // 0: every placement keeps the whole window on the copy (Kwatra, Zhou). > 0: a placement only
  // needs the window's anchor texel on the copy (anchor_margin texels inside its border), for
  // windows up to this many texels a side with no texel farther than max_window / 2 from the
  // anchor (each is correlated on the smallest of three FFT planes its reach allows); the SSD is
  // over the synthesized texels the copy covers, each one it does not cover adding
  // uncovered_cost, over the window's synthesized count. A window
  // kept on the copy puts a sample texel under its anchor only that far from the border, so the
  // border band of a small sample is drawn on less than its centre: quilting a 96-texel sample with
  // 49-texel windows drifts to the centre's statistics. Not with a constraint term (painting).
  int max_window = 0;
  double uncovered_cost = 0;  // per uncovered synthesized texel, squared feature units
  int anchor_margin = 0;
};

class PatchMatcher {
 public:
  // `copies` must outlive the matcher. Every copy is prepared once (FFTs of its feature channels,
  // of its squared norm and of its constraint).
  PatchMatcher(const std::vector<RotatedSample>& copies, const PatchMatcherOptions& options);
  ~PatchMatcher();
  PatchMatcher(const PatchMatcher&) = delete;
  PatchMatcher& operator=(const PatchMatcher&) = delete;

  // The placement of least cost over every copy and translation keeping the window inside the copy.
  // Windows larger than every copy return found = false.
  MatchResult BestMatch(const MatchWindow& window) const { return ChooseMatch(window, 0, 0); }
  // Kwatra's stochastic choice: placement t with probability proportional to
  // exp(-(C(t) - C_min) / temperature), drawn with `uniform` in [0, 1); temperature 0: the least cost.
  MatchResult ChooseMatch(const MatchWindow& window, double temperature, double uniform) const;
  // Among the placements whose cost is at most (1 + tolerance) x the least cost + floor, the one of
  // least key(placement) (ties: the first copy and texel): the caller's choice among near-equals.
  MatchResult ChooseNearBest(const MatchWindow& window, double tolerance, double floor,
                             const std::function<double(const MatchResult&)>& key) const;
  // All costs for one copy (row-major over valid (u, v), from (u_min, v_min): 0, 0 unless
  // placements may leave the copy), for tests and the brute-force comparison.
  std::vector<double> Costs(const MatchWindow& window, int copy, int* valid_w, int* valid_h, int* u_min = nullptr,
                            int* v_min = nullptr) const;

 private:
  struct Impl;
  struct WindowSpectra;
  // Null for a window larger than every copy.
  std::unique_ptr<WindowSpectra> Prepare(const MatchWindow& window) const;
  std::vector<double> CostsFor(const MatchWindow& window, const WindowSpectra& spectra, int copy, int* valid_w,
                               int* valid_h, int* u_min, int* v_min) const;
  // Every copy's costs for the window (false: the window is larger than every copy).
  struct AllCosts;
  bool CostsOfAll(const MatchWindow& window, AllCosts* all) const;
  std::vector<double> LeavingCostsFor(const MatchWindow& window, const WindowSpectra& spectra, int copy, int* valid_w,
                                      int* valid_h, int* u_min, int* v_min) const;
  std::unique_ptr<Impl> impl_;
};

// The same costs by direct summation: O(window * placements * channels). The reference the FFT
// path is tested and benchmarked against.
std::vector<double> BruteForceCosts(const RotatedSample& copy, const MatchWindow& window, double constraint_weight,
                                    int* valid_w, int* valid_h);
// The same for placements that may leave the copy (max_window > 0), from (u_min, v_min).
std::vector<double> BruteForceLeavingCosts(const RotatedSample& copy, const MatchWindow& window, double uncovered_cost,
                                           int anchor_margin, int* valid_w, int* valid_h, int* u_min, int* v_min);

}  // namespace mesocap
