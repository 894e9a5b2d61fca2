// Mirror symmetry of a material's appearance. Many materials look statistically the same turned
// half round about the normal (plain weaves, corduroy, anything isotropic), many also mirrored
// about the patch's x or y axis (corduroy, stones; not a weave whose fibres twist one way), and
// some turned a quarter round (stones, anything isotropic). For such a material a slice measured
// at (light, view) also stands for the imaged pair (M light, M view), its oriented subbands
// imaged with it (ImagedStatistics). On the rig every
// image of a board lands on another board of its ring, so each board's statistics gain the lights
// the boards it pools with saw (the camera's side of each), from other parts of the material.
// Whether an image holds is tested on the session's own top view (CheckMirrorSymmetry).
#pragma once

#include <array>
#include <span>
#include <string>
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
// Their names, in order (header-only: the command line names them without loading the library).
inline constexpr std::array<const char*, kMirrorImageCount> kMirrorImageNames = {
    "mirror_x", "mirror_y", "half_turn", "quarter_turn", "three_quarter_turn", "mirror_diagonal", "mirror_antidiagonal"};
using MirrorImageSet = std::array<bool, kMirrorImageCount>;  // per MirrorImages() entry
inline constexpr MirrorImageSet kEveryMirrorImage = {true, true, true, true, true, true, true};
// The set of the images named (kMirrorImageNames; unknown names are ignored: the command line
// checks them).
inline MirrorImageSet MirrorImagesNamed(const std::vector<std::string>& names) {
  MirrorImageSet set{};
  for (const std::string& name : names)
    for (size_t k = 0; k < kMirrorImageNames.size(); ++k) set[k] = set[k] || name == kMirrorImageNames[k];
  return set;
}

// `statistics` of the imaged texture. The steerable band at frequency angle pi o / K is filtered
// by cos^(K-1) of the angle from it: an image takes it to the band at its imaged angle, negated
// (Q(p) -> -Q(1 - p)) for even K when that angle wraps by pi (x -> -x negates orientation 0, y -> -y
// the others, the half turn all). Images must map the K orientations onto each other (K = 4).
SliceStatistics ImagedStatistics(const SliceStatistics& statistics, const MirrorImage& image, int orientations);
// The same as a map of the bands, for blending imaged statistics without a copy
// (BlendSliceStatistics): statistics of `band_count` bands per channel.
BandMap ImagedBands(const MirrorImage& image, int band_count, int orientations);

// Whether each image holds, tested on the top view's own slices: for each measured light whose
// image lies at least 10 deg from it and within 10 deg of a measured light, the statistics
// interpolated at the imaged light are compared with the light's own statistics, imaged, by a
// distance (the first channel's, brightness or R, pixel and subband W1, each over the measured
// histogram's 10-90% spread, summed). Two medians over the lights:
//  - `ratio`: that distance over the interpolation's own error at the light (its statistics
//    against those interpolated from the other lights). At most kMirrorCheckLimit: the image is
//    about as near as the interpolation gets (a light's shading does not change under it).
//  - `against_measured`: that distance over the distance of the statistics as measured (not
//    imaged). At most kMirrorCheckTolerance: imaging the subbands does not make them worse (the
//    texture's orientations map as the image says). Not asked of the half turn, which only negates
//    the bands.
// Both mirrors about the axes holding, the half turn (their product) holds.
// Calibrated 100-shot sessions (seeds 21-24): against_measured of weave's mirrors about the axes
// 1.05-1.18, its other band-moving images 1.79-2.53 (its fibres twist one way; warp and weft
// differ), corduroy's mirrors 0.80-1.00 and its quarter turns and diagonal mirrors 8.4-12.1 (its
// wales run along y), stones' 0.58-0.89; ratios: weave's half turn 0.93-1.16, corduroy's 1.17-1.26,
// stones' images 0.96-1.28. True slices: mirror_symmetry_test and docs/reconstruction.md.
inline constexpr double kMirrorCheckLimit = 2.5, kMirrorCheckTolerance = 1.03;
struct MirrorSymmetryCheck {
  bool tested = false;             // false: the option was off, or too few top-view lights
  std::array<double, kMirrorImageCount> ratio{};  // per MirrorImages() entry (0: not measurable)
  // The imaged statistics' distance over the distance of the statistics as measured, both to those
  // at the imaged light: above 1, imaging them makes them worse.
  std::array<double, kMirrorImageCount> against_measured{};
  std::array<int, kMirrorImageCount> lights{};    // lights tested
  MirrorImageSet holds{};
  // The images the check may find: those the operator named (StatisticalBtfOptions::
  // mirror_images_allowed). `holds` is never outside them.
  MirrorImageSet allowed = kEveryMirrorImage;
  Json ToJson() const;
};
// `max_gap_deg`: how far from a measured light an imaged light may lie (10 deg: the 10 above).
// `allowed`: the images it may find (the others are still measured, never held).
MirrorSymmetryCheck CheckMirrorSymmetry(const MeasuredView& top, int orientations, double min_separation_deg,
                                        double max_gap_deg = 10, const MirrorImageSet& allowed = kEveryMirrorImage);

// The index of the direction in `directions` nearest `direction` if within `within_deg`, else -1:
// the view an image of a view lands on (WithMirrorImages, and guidance's CoverageOptions::images).
int NearestWithin(std::span<const Eigen::Vector3d> directions, const Eigen::Vector3d& direction, double within_deg);

// `views` (measured) with the images of each that `use` names (per MirrorImages() entry): an image
// within `pool_deg` of a view (measured or already an image) lends its lights to the nearest such
// view (MeasuredView::borrowed: a blend reads the source's statistics through the image's band
// map, ImagedBands); any other becomes a view of its own. An image's light within
// `min_separation_deg` of a light the view already has is left out. Mean colours follow their
// slices.
std::vector<MeasuredView> WithMirrorImages(const std::vector<MeasuredView>& views, const MirrorImageSet& use,
                                           double pool_deg, double min_separation_deg);

}  // namespace mesocap
