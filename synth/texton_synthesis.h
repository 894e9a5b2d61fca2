// Synthesis of a texton map in the plane: Tong et al. 2002's surface-texton formulation (every
// neighbourhood distance summed from the textons' dot-product matrix Gamma, candidates from the
// k-coherence search) run as Lefebvre & Hoppe 2005's parallel per-texel synthesis on the Gaussian
// stack of texton maps (texton_analysis.h). Output texels hold sample coordinates, so the result
// is a texture-coordinate map like every other method's.
//
// Per level l, coarsest first, with spacing h = 2^l between a level's neighbourhood texels:
// - Upsampling: each texel of the level above spawns four children whose coordinates continue its
//   own by h (L&H §3.2), then each child is jittered by up to `jitter` x h texels. The coarsest
//   level starts from random sample coordinates.
// - Correction (L&H §3.4): `passes` passes, each split into four sub-passes over the 2 x 2
//   interleaved texel classes, so a texel is corrected against neighbours already corrected in the
//   same pass. A texel's query is the N x N neighbourhood of labels at its neighbours'
//   coordinates; a candidate sample texel's is the labels at its own coordinate plus h x the
//   offset. Candidates: for each of the 3 x 3 nearest output neighbours, the sample texel that
//   continues its coordinate, and that texel's k - 1 most similar sample texels (k-coherence); a
//   candidate continuing neighbours is favoured (`coherence`).
// Why: Tong's pyramid with scanline passes smeared structured photographs (a brick wall) into
// horizontal streaks: a pyramid level of a 96-texel sample holds 24 x 24 positions, and scanline
// order lets one choice propagate along a row. The stack keeps every sample position at every
// level, and the interleaved sub-passes correct texels against neighbours on all sides.
//
// - A sample texel that is the source of one of the texel's 8 neighbours is never chosen (it would
//   stretch one sample texel across the output: a streak).
// - Similar-texel lists exclude texels within max(2, h) of the texel itself (near copies on a
//   blurred level, direct neighbours on the finest) and are ranked by the exact Gamma distance among the
//   nearest by a principal-component summary of the neighbourhoods.
// - Every sample texel is a candidate; a neighbourhood slot beyond the sample costs half the
//   typical distance between two sample texels (see kOutsideCost), so the output draws on the
//   whole sample, borders included.
// - The output wraps around, so the result tiles; each sub-pass reads the state at its start, so
//   the map is the same for any thread count.
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
  int k = 11;                     // k-coherence (Tong: 11; 1 keeps only coherent continuations)
  int neighbourhood = 5;          // N: N x N at a texel's level, spaced 2^l (L&H: 5)
  int levels = 0;                 // stack levels used (0: all the analysis has)
  int passes = 2;                 // correction passes per level (L&H: 2)
  double jitter = 0.5;            // upsampled coordinates move by up to this x the level's spacing
  // A neighbour's continuation wins against a candidate up to 1 / (1 - coherence) times closer
  // (Ashikhmin's and Hertzmann's coherence bias): fewer, longer patches.
  double coherence = 0.5;
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
