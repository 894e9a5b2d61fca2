// Patch fitting by min-cut (Kwatra et al. 2003; Zhou 2005 §III-B and §IV-A): inside a work window,
// every texel keeps its old value (label "old") or takes the new patch's (label "new"), cutting
// where the two agree best. Old seams are kept as Kwatra's seam nodes, so a new patch may also
// heal a bad earlier cut. Painting adds Zhou's data term D_p(sigma) = w |m_sigma(p) - m0(p)|.
// The graph is solved with Boykov-Kolmogorov max-flow (Debian's libmaxflow).
#pragma once

#include <cstdint>
#include <vector>

#include "core/image.h"
#include "synth/patch_matching.h"
#include "synth/synth_map.h"

namespace mesocap {

// The output under construction: the map, the features it copies, which texels are filled, and
// for painting the sample's feature mask and the user's target m0.
struct SynthCanvas {
  SynthMap map;
  Image features;                    // output features (width x height x F)
  std::vector<uint8_t> synthesized;  // 1 where the map is filled
  const Image* sample_features = nullptr;  // the unrotated sample
  const Image* sample_mask = nullptr;      // painting: 1 channel, 1 = feature; or null
  const Image* target = nullptr;           // painting: m0 over the output; or null
  int next_patch = 0;

  SynthCanvas(int width, int height, const Image& sample, std::string method);
  // The sample mask value the output texel copies (0 without a mask).
  float MaskAt(int x, int y) const;
};

// A placed patch: the rotated copy, the copy's texel under the window origin, the window.
struct PlacedPatch {
  const RotatedSample* copy = nullptr;
  int u0 = 0, v0 = 0;
  int x0 = 0, y0 = 0, width = 0, height = 0;
  const float* NewFeatures(int x, int y) const { return copy->features.pixel(u0 + x - x0, v0 + y - y0); }
};

// Which window texels may change.
enum class FitFreedom : uint8_t { kFree, kForceOld, kForceNew };

struct CutResult {
  std::vector<uint8_t> take_new;   // per window texel (row-major), 1 = new
  double seam_cost = 0;            // sum of the cut's smoothness edges
  int seam_edges = 0;              // neighbouring pairs the cut separates
  double mean_seam_cost() const { return seam_edges ? seam_cost / seam_edges : 0.0; }
  int new_texels = 0;
};

struct FitOptions {
  double data_weight = 0;  // w of the painting data term (0: synthesis, smoothness only)
  double step_weight = 0.5;  // weight of the step across the cut in the smoothness term (0: Kwatra's M)
};

// Default freedom: unfilled texels must take the new patch; filled texels on the window's edge
// whose outside neighbour is filled keep their value (the patch stays inside the window).
std::vector<FitFreedom> DefaultFreedom(const SynthCanvas& canvas, const PlacedPatch& patch);

CutResult FitPatch(const SynthCanvas& canvas, const PlacedPatch& patch, const std::vector<FitFreedom>& freedom,
                   const FitOptions& options = {});

// Writes the cut's new texels into the canvas under a fresh patch id.
void CommitPatch(SynthCanvas* canvas, const PlacedPatch& patch, const CutResult& cut);

// Mean L2 feature step between 4-neighbours of the sample: the yardstick of seam costs.
double MeanNeighbourStep(const Image& features);

}  // namespace mesocap
