// Graphcut quilting on a dense atlas mesh (Zhou et al. 2005 §III-B): the atlas' texels are the
// dense mesh's vertices (mesh/atlas_texels.h), and each gets a sample coordinate, patch by patch:
// - take the most constrained unfilled texel v (most filled neighbours, across chart borders too);
// - its work patch: the faces around v within the work window's reach, grown face by face, laid
//   flat by LSCM (mesh/lscm.h); refused, and the window shrunk by 0.8, while the faces are not a
//   disk or the flattening stretches some face's area by more than T_d = 4;
// - its work image: a (2 r_w + 1)^2 grid at one sample texel per cell, turned so that the
//   field's mean direction over the patch runs along +x and t up (Zhou matches 72 rotated copies of
//   the sample against the field's mean orientation; turning the work image is the same alignment
//   without the copies' nearest-texel resampling). Each cell is the surface point under it; it is
//   filled when the atlas texel there is, with that texel's value and its patch's orientation;
// - entire-patch matching (FFT SSD over the filled cells, synth/patch_matching.h), graphcut fitting
//   with old seams (synth/graphcut_fit.h), the cut accepted when its mean cost is at most
//   T_c x the sample's mean neighbour step, else the window shrinks by 0.8 down to 4 texels;
// - every atlas texel of the patch's faces whose cell took the new patch gets the sample
//   coordinate under its own position in the work image (continuous: texels between cells continue
//   the patch), and the turn between the patch's axes and its tangent frame.
// The map's rotation_deg is that turn: the texel shows the sample turned by it against its frame's
// s axis (synth_map.h's convention), so renders and bakes read directions through it.
#pragma once

#include <cstdint>

#include "core/image.h"
#include "core/progress.h"
#include "core/status.h"
#include "mesh/atlas.h"
#include "mesh/atlas_texels.h"
#include "mesh/tangent_frames.h"
#include "mesh/triangle_mesh.h"
#include "synth/synth_map.h"

namespace mesocap {

struct SurfaceQuiltOptions {
  // r_w in sample texels; 0: Zhou's 32, or the largest window a smaller sample holds. (The plane's
  // quilt takes a quarter of the side; on the sphere test's 64-texel brick that smaller window
  // cut more and lost to a planar projection in subband statistics, 0.162 against 0.148, where
  // the whole-sample window gives 0.122.)
  int patch_radius = 0;
  int min_patch_radius = 4;        // Zhou: shrink down to 4
  double shrink = 0.8;             // Zhou: r_w <- 0.8 r_w
  double seam_threshold = 2.0;     // T_c, in units of the sample's mean neighbour feature step (the plane's)
  double max_area_distortion = 4;  // T_d (Zhou: 4)
  double texel_size = 0;           // surface length of one sample texel (0: the mesh's mean edge length)
  uint32_t seed = 1;
  int num_threads = -1;
  Status Check(int sample_width, int sample_height) const;
  int EffectiveRadius(int sample_width, int sample_height) const;
};

struct SurfaceQuiltReport {
  int patches = 0, rejected_cuts = 0, rejected_flattenings = 0;
  int patch_radius = 0;
  int texels = 0;                  // dense texels (atlas texels inside charts)
  int chart_crossing_patches = 0;  // patches whose faces span more than one chart
  double texel_size = 0;
  double mean_seam_cost = 0, sample_neighbour_step = 0;
  double seconds_flattening = 0, seconds_matching = 0, seconds_cutting = 0, seconds = 0;
};

// A map of atlas.size x atlas.size texels (the atlas' texels inside charts filled, the rest left
// at patch -1: FillAtlasGutter extends it) into `sample_features`' texels.
StatusOr<SynthMap> SurfaceQuiltSynthesis(const TriangleMesh& mesh, const TangentFrames& frames, const Atlas& atlas,
                                         const AtlasTexels& texels, const Image& sample_features,
                                         const SurfaceQuiltOptions& options, SurfaceQuiltReport* report,
                                         const ProgressFn& progress = nullptr);

// The sample coordinate a texel's patch gives a point `offset` away from the texel on the surface
// (tangent to it), `s`, `t` the frame there: the patch's x axis lies rotation_deg from s toward t,
// its rows run against its y axis, one sample texel per `texel_size`.
Eigen::Vector2d ContinueAtlasCoordinate(const SynthMap& map, size_t texel, const Eigen::Vector3d& s, const Eigen::Vector3d& t,
                                        const Eigen::Vector3d& offset, double texel_size);

}  // namespace mesocap
