// Mirror symmetry of a material's appearance. Many materials look statistically the same turned
// half round about the normal (plain weaves, corduroy, anything isotropic), many also mirrored
// about the patch's x or y axis (corduroy, stones; not a weave whose fibres twist one way), and
// some turned a quarter round (stones, anything isotropic). For
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

// An image of the patch frame (z = normal): `plane` acts on a direction's x and y.
struct MirrorImage {
  const char* name;
  Eigen::Matrix2d plane;
  Eigen::Vector3d Of(const Eigen::Vector3d& direction) const;
};
// The symmetries of the square but the identity: the mirrors x -> -x and y -> -y, the half turn,
// the quarter turns (counter-clockwise, clockwise), the mirrors about the diagonals.
inline constexpr int kMirrorImageCount = 7;
const std::array<MirrorImage, kMirrorImageCount>& MirrorImages();
using MirrorImageSet = std::array<bool, kMirrorImageCount>;  // per MirrorImages() entry

// `statistics` of the imaged texture. The steerable band at frequency angle pi o / K is filtered
// by cos^(K-1) of the angle from it: an image takes it to the band at its imaged angle, negated
// (Q(p) -> -Q(1 - p)) for even K when that angle wraps by pi (x -> -x negates orientation 0, y -> -y
// the others, the half turn all). Images must map the K orientations onto each other (K = 4).
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
// Calibrated 100-shot sessions (seeds 21-24): weave's half turn 0.93-1.16, its other images
// 1.77-3.42 (its fibres twist one way; warp and weft differ); corduroy's mirrors about the axes
// and half turn 0.73-1.26, its quarter turns and diagonal mirrors 17.5-22.8 (its wales run along
// y); every image of stones 0.96-1.28. True slices: mirror_symmetry_test.
inline constexpr double kMirrorCheckTolerance = 1.4, kMirrorCheckLimit = 2.5;
struct MirrorSymmetryCheck {
  bool tested = false;             // false: the option was off, or too few top-view lights
  std::array<double, kMirrorImageCount> ratio{};  // per MirrorImages() entry (0: not measurable)
  std::array<int, kMirrorImageCount> lights{};    // lights tested
  MirrorImageSet holds{};
  Json ToJson() const;
};
MirrorSymmetryCheck CheckMirrorSymmetry(const MeasuredView& top, int orientations, double min_separation_deg);

// `views` with the images of each that `use` names (per MirrorImages() entry): an image within
// `pool_deg` of a view (measured or already an image) adds its lights and statistics to the
// nearest such view; any other becomes a view of its own. Measured lights come first; an image's
// light within `min_separation_deg` of a light the view already has is left out. Mean colours
// follow their slices.
std::vector<MeasuredView> WithMirrorImages(const std::vector<MeasuredView>& views, const MirrorImageSet& use,
                                           int orientations, double pool_deg, double min_separation_deg);

}  // namespace mesocap
