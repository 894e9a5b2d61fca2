// Applying a synthesis map to every representation of the sample: a BTF slice by slice
// (streamed: one output slice and the sample slices it needs at a time), a PTM's coefficients, a
// plain image. A texel of a rotated patch looks the sample up at directions turned by -rotation
// (phi_i and phi_o minus the rotation), blended from the sample's slices by its own direction
// interpolation (Delaunay triangle of lights within the view, rings of views: reconstruct/).
#pragma once

#include <filesystem>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "core/image.h"
#include "core/status.h"
#include "reconstruct/direction_interpolation.h"
#include "reconstruct/ptm.h"
#include "synth/exemplar.h"
#include "synth/synth_map.h"

namespace mesocap {

// The sample's slices seen as a function of (light, view): which slices and weights make the
// slice at any pair of directions.
class SliceDirectionLookup {
 public:
  static StatusOr<SliceDirectionLookup> Create(const std::vector<ExemplarSlice>& slices);
  // Slices and weights (summing to one) for the pair; a measured pair returns that slice alone.
  std::vector<WeightedIndex> Weights(const Eigen::Vector3d& light, const Eigen::Vector3d& view) const;

 private:
  struct View {
    Eigen::Vector3d direction;
    std::vector<int> slices;
    std::shared_ptr<LightInterpolator> lights;  // null when the view has fewer than 3 usable lights
  };
  std::vector<ExemplarSlice> slices_;
  std::vector<View> views_;
  std::shared_ptr<ViewInterpolator> view_rings_;  // null with a single view
};

// The directions a texel turned by `rotation_deg` looks up in the sample.
Eigen::Vector3d TurnDirection(const Eigen::Vector3d& direction, double rotation_deg);

struct ApplyOptions {
  int cache_slices = 48;  // decoded sample slices kept for reuse across rotations
  int num_threads = -1;
};

// Streams the map over a BTF exemplar: calls `write(k, slice)` for each requested output slice k
// (indices into exemplar.slices) in parallel; nothing is kept beyond the cache.
Status ApplyMapToBtf(const SynthMap& map, const Exemplar& exemplar, const std::vector<int>& slices,
                     const std::function<Status(int, const Image&)>& write, const ApplyOptions& options = {},
                     const ProgressFn& progress = nullptr);

// One output slice of the map over a BTF exemplar (the unit ApplyMapToBtf runs per slice).
StatusOr<Image> SynthesizedSlice(const SynthMap& map, const SliceDirectionLookup& lookup,
                                 const ExemplarSlice& target, const std::function<StatusOr<Image>(int)>& read_slice);

// The PTM coefficients of a light polynomial turned by `rotation_deg` (exact: a quadratic in the
// light's (lu, lv) stays quadratic under rotation). a, out: 6 coefficients (lu^2, lv^2, lu lv, lu, lv, 1).
void RotatePtmCoefficients(const float* a, double rotation_deg, float* out);

// The synthesized PTM: each texel's polynomial(s) from its source, turned by its rotation.
Ptm ApplyMapToPtm(const SynthMap& map, const Ptm& sample);

}  // namespace mesocap
