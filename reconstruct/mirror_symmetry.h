// Mirror symmetry of a material's appearance. Many materials look statistically the same turned
// half round about the normal (plain weaves, corduroy, anything isotropic), and many also mirrored
// about the patch's x or y axis (corduroy, stones; not a weave whose fibres twist one way). For
// such a material a slice measured at (light, view) also stands for the imaged pair
// (M light, M view), its oriented subbands imaged with it (ImagedStatistics). On the rig every
// image of a board lands on another board of its ring, so each board's statistics gain the lights
// the boards it pools with saw (the camera's side of each), from other parts of the material.
// Whether an image holds is tested on the session's own top view (CheckMirrorSymmetry).
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>

#include "core/json.h"
#include "reconstruct/slice_statistics.h"

namespace mesocap {

struct MeasuredView;

// An image of the patch frame (z = normal): a direction's components times `sign`.
struct MirrorImage {
  const char* name;
  Eigen::Vector3d sign;
};
// x -> -x, y -> -y, and both (the half turn).
const std::array<MirrorImage, 3>& MirrorImages();

// `statistics` of the imaged texture. The steerable band at frequency angle pi o / K (its filter
// cos^(K-1) of the angle from it) goes to angle pi (K - o) / K under a mirror and stays under the
// half turn; the filter's odd power for even K negates the band (Q(p) -> -Q(1 - p)) where the
// image turns its angle by pi: orientation 0 under x -> -x, the others under y -> -y, all under
// the half turn.
SliceStatistics ImagedStatistics(const SliceStatistics& statistics, const MirrorImage& image, int orientations);

// Whether each image holds, tested on the top view's own slices. For each measured light whose
// image lies at least 10 deg from it and within 10 deg of a measured light: the distance from its
// statistics, imaged, to those interpolated at the imaged light, over the distance from its
// statistics to those interpolated at its own light from the other lights (the interpolation's
// own error there); the median of that ratio over the lights. A finite patch is not exactly its
// own image, and without noise the interpolation is nearly exact: so an image holds when its
// ratio is at most kMirrorCheckTolerance times the best image's (or times 1 if the best is
// below 1), the best being at most kMirrorCheckLimit; both mirrors holding, the half turn (their
// product) holds. The distance: the first channel's (brightness, or R) pixel and subband W1, each
// over the measured histogram's 10-90% spread, summed.
// Calibrated 100-shot sessions (seeds 21-24): weave's mirrors 1.77-1.94 against its half turn's
// 0.93-1.16 (its fibres twist one way), every image of corduroy 0.73-1.26 and of stones 1.04-1.19.
// True slices (mirror_symmetry_test): weave's mirrors 2.41-2.48 against 0.98, stones 1.43-1.71,
// corduroy 0.50-1.18.
inline constexpr double kMirrorCheckTolerance = 1.4, kMirrorCheckLimit = 2.5;
struct MirrorSymmetryCheck {
  bool tested = false;             // false: the option was off, or too few top-view lights
  std::array<double, 3> ratio{};   // per MirrorImages() entry (0: not measurable)
  std::array<int, 3> lights{};     // lights tested
  std::array<bool, 3> holds{};
  Json ToJson() const;
};
MirrorSymmetryCheck CheckMirrorSymmetry(const MeasuredView& top, int orientations, double min_separation_deg);

// `views` with the images of each that `use` names (per MirrorImages() entry): an image within
// `pool_deg` of a view (measured or already an image) adds its lights and statistics to the
// nearest such view; any other becomes a view of its own. Measured lights come first; an image's
// light within `min_separation_deg` of a light the view already has is left out. Mean colours
// follow their slices.
std::vector<MeasuredView> WithMirrorImages(const std::vector<MeasuredView>& views, const std::array<bool, 3>& use,
                                           int orientations, double pool_deg, double min_separation_deg);

}  // namespace mesocap
