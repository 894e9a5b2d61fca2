// Graphcut quilting in the plane (Zhou et al. 2005 §III-B, after Kwatra et al. 2003) and
// graphcut texture painting (Zhou §IV): repeatedly take the most constrained unfilled texel, open a
// work window of radius r_w around it, place the sample (or a rotated copy) by entire-patch
// matching, fit it by min-cut, and accept the piece if the cut's mean cost is below T_c, else shrink
// r_w by 0.8 down to 4 and try again.
#pragma once

#include <cstdint>
#include <string>

#include "core/image.h"
#include "core/progress.h"
#include "core/status.h"
#include "synth/synth_map.h"

namespace mesocap {

struct QuiltOptions {
  int width = 512, height = 512;  // output texels
  // Work-window radius r_w (Zhou: 32 for a 512 x 512 output); 0 picks min(32, sample side / 4).
  int patch_radius = 0;
  int min_patch_radius = 4;        // Zhou: shrink down to 4
  double shrink = 0.8;             // Zhou: r_w <- 0.8 r_w when the seam is too costly
  // T_c: a cut is accepted when its mean cost per separated neighbour pair is at most this many
  // times the sample's mean neighbour feature step.
  double seam_threshold = 2.0;
  // Placement choice among the matches (Kwatra et al. 2003): probability proportional to
  // exp(-(C - C_min) / (randomness * sigma^2)), sigma^2 the sample's feature variance; 0 takes the
  // least cost (Zhou). A little randomness keeps the output from drawing on one region only.
  double randomness = 0.0;
  int rotations = 1;               // rotated copies of the sample, evenly spaced (Zhou: 72); 1 = none
  // Placements may leave the sample as long as the texel the patch is for lands on it (a quarter
  // of r_w inside the border), so the sample's border band is drawn on as often as its centre; a
  // synthesized texel a placement does not cover costs half the mean squared step between two
  // sample texels (PatchMatcherOptions::max_window). Zhou keeps the work window inside the sample
  // (false), which drifts to the centre's statistics: on the 20 photographs (96 -> 256, three
  // seeds) the subband ratio to random tiling went 1.10x -> 0.82x (geometric mean), textures losing
  // to random tiling 9 -> 4, at 0.9-1.2x the time (docs/synthesis.md). Quilting only, not painting.
  bool whole_sample = true;
  // Usage balance (quilting, not painting): among the placements costing at most (1 +
  // usage_tolerance) x the least cost + 0.1 sigma^2, the one of least cost + usage_weight x 2
  // sigma^2 x (crowding - 1), the crowding being how often the sample box of radius r_w / 2 around
  // the texel under the patch's anchor is already used, over its share under uniform use; 0: the
  // least cost (Zhou). The least cost favours bland regions (they match anything), so the output's
  // statistics drift from the sample's. On the 20 photographs (96 -> 256, three seeds) 0.5 takes the
  // subband ratio to random tiling from 0.82x to 0.62x (fur 1.43x -> 0.56x, rock 1.07x -> 0.85x; 17
  // -> 19 of 20 at or below it), but at 1.5-2.0x the time (more cuts are refused), and brick courses
  // break more often: off by default (docs/synthesis.md).
  double usage_weight = 0;
  double usage_tolerance = 0.5;
  uint32_t seed = 1;
  int num_threads = -1;
  Status Check(int sample_width, int sample_height) const;
  int EffectiveRadius(int sample_width, int sample_height) const;
};

struct PaintOptions {
  double transition_width = 8;     // texels over which m0 falls linearly from 1 to 0 outside F
  double match_weight = 1.0;       // joint search: mask term weight, in units of the feature variance
  double data_weight = 2.0;        // constrained graphcut data term, in units of the mean neighbour step
  bool verbatim = false;           // copy the whole sample feature once (Kwatra's interactive merging)
  int max_repair_patches = 400;    // patches placed over texels still violating the constraint
};

struct QuiltReport {
  int patches = 0, rejected_cuts = 0, repair_patches = 0;
  int patch_radius = 0;            // r_w derived from the sample
  double mean_seam_cost = 0;       // over accepted cuts, per separated pair (feature units)
  double sample_neighbour_step = 0;
  double seconds_matching = 0, seconds_cutting = 0, seconds = 0;
};

// Quilts `sample_features` (one vector per texel) into a map of options.width x height.
// `built`, if given, receives the features the method assembled patch by patch (what applying the
// map to the sample must reproduce bit for bit).
StatusOr<SynthMap> QuiltSynthesis(const Image& sample_features, const QuiltOptions& options, QuiltReport* report,
                                  const ProgressFn& progress = nullptr, Image* built = nullptr);

// m0 of Zhou §IV-B: 1 inside the user's target region, falling linearly to 0 across a transition
// zone of `width` texels outside it.
Image TargetConstraint(const Image& target_mask, double width);

// Graphcut painting: quilts with the joint search and the constrained graphcut so that the
// sample's feature (sample_mask > 0.5) lands where target_mask > 0.5, then repairs texels that
// still break the constraint. Masks: 1 channel, sample size and output size.
StatusOr<SynthMap> PaintSynthesis(const Image& sample_features, const Image& sample_mask, const Image& target_mask,
                                  const QuiltOptions& options, const PaintOptions& paint, QuiltReport* report,
                                  const ProgressFn& progress = nullptr, Image* built = nullptr);

}  // namespace mesocap
