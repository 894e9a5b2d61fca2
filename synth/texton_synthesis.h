// Synthesis of a texton map in the plane (Tong et al. 2002 §5): multi-resolution, two passes, every
// neighbourhood distance summed from the textons' dot-product matrix Gamma, candidates from the
// k-coherence search. Output texels hold sample coordinates, so the result is a texture-coordinate
// map like every other method's.
//
// - The coarsest level starts from random sample coordinates and is synthesized in scanline order
//   with the causal half of the N x N neighbourhood (Wei & Levoy).
// - Each finer level: pass one takes every texel's coordinate from its parent's (2 s + the child's
//   offset); pass two resynthesizes it in scanline order with its full N x N neighbourhood at this
//   level and the P x P neighbourhood of its parent at the level above (the two-level
//   neighbourhood), the candidates formed from this level's neighbourhood only.
// - `passes` resynthesis passes follow the first at every level (the coarsest too, without a
//   parent). Tong makes one; two are the default here: measured on the virtual-rig weave and
//   stones (128 x 128 samples), the second pass cuts the seams between incoherent neighbours and
//   lifts the share of queries where k-coherence finds the full search's best from 0.79-0.80 to
//   0.85-0.91 (see the texton issue's closing note).
// - Neither paper gives the neighbourhoods' sizes. N = 9 and P = 5 are measured: against 5 x 5,
//   the 9 x 9 neighbourhood keeps the stones' cells whole (subband statistics 1.5x random
//   tiling's become 1.16x) and the weave's rows straight (1.26x become 0.73x).
// - Candidates are sample texels whose whole neighbourhood, and their parent's, lies inside the
//   sample; the output wraps around, so the result tiles.
// - Resynthesis passes sweep bands of 32 rows in parallel; a band reads the other bands' rows as
//   they were when the pass began, so the map is the same for any thread count.
#pragma once

#include <cstdint>
#include <vector>

#include "core/progress.h"
#include "core/status.h"
#include "synth/synth_map.h"
#include "synth/texton_analysis.h"

namespace mesocap {

enum class TextonSearch { kCoherence, kFull };

struct TextonSynthesisOptions {
  int width = 512, height = 512;  // output texels
  int k = 11;                     // k-coherence (Tong: 11; 1 for "natural" textures)
  int neighbourhood = 9;          // N: N x N at a texel's own level (see above)
  int parent_neighbourhood = 5;   // P: P x P at the level above, in pass two (see above)
  int levels = 0;                 // pyramid levels used (0: all the analysis has)
  int passes = 2;                 // full-neighbourhood resynthesis passes per level (Tong: 1)
  TextonSearch search = TextonSearch::kCoherence;
  // Share of the queries also answered by the full search, to report how often the k-coherence
  // candidate is the full search's best (0: none). Counted in each level's last pass, whose
  // choices are the output (earlier passes' choices are all revisited).
  double audit_fraction = 0;
  uint32_t seed = 1;
  int num_threads = -1;
  Status Check() const;                               // the options alone
  Status CheckSample(int width, int height) const;    // a sample the neighbourhood fits in
  Status Check(const TextonAnalysis& analysis) const;  // both, on the sample analysed
};

struct TextonLevelReport {
  long queries = 0;
  double mean_candidates = 0;
  long audited = 0;
  double full_search_agreement = 0;
};

struct TextonSynthesisReport {
  int levels = 0;
  std::vector<TextonLevelReport> per_level;  // finest first
  long queries = 0;
  double mean_candidates = 0;  // distinct candidates per query
  long audited = 0;            // queries also answered by full search
  double full_search_agreement = 0;  // of those, the share where both found the same best distance
  double seconds_neighbours = 0, seconds_synthesis = 0, seconds = 0;
};

StatusOr<SynthMap> TextonSynthesis(const TextonAnalysis& analysis, const TextonSynthesisOptions& options,
                                   TextonSynthesisReport* report, const ProgressFn& progress = nullptr);

}  // namespace mesocap
