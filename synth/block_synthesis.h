// Block synthesis with an exact rejection search (the PTM synthesis paper, §IV and §VII, after
// Efros & Freeman's image quilting): blocks of the sample are laid in raster order, each chosen
// by the L2 distance between its neighbourhood (the overlap with what is already placed: the
// left strip, the top strip, or both) and the output's, and joined along the minimum-error
// boundary cut through the overlap. For a PTM the features are its Legendre coefficients
// (reconstruct/ptm_legendre.h), so distances and cuts are L2 distances between reflectance
// functions.
//
// The search is exact: every neighbourhood of the sample is projected once onto the first
// principal directions of the neighbourhood ensemble (an orthonormal basis: the SVD of a sample
// of them). The squared distance of the projections is a lower bound of the full distance, so a
// candidate whose bound exceeds the threshold (the best full distance so far, times 1 +
// tolerance) is rejected without computing its distance; the survivors are evaluated in order of
// their bound until the bound passes the threshold. It returns exactly what brute force returns.
#pragma once

#include <algorithm>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/image.h"
#include "core/progress.h"
#include "core/status.h"
#include "synth/synth_map.h"

namespace mesocap {

enum class BlockSearch { kRejection, kBruteForce };
// The bounds' basis: the principal directions of the sample's neighbourhoods, or the first
// Walsh-Hadamard functions in sequency order (the unfolded vector zero-padded to a power of two),
// which the paper also suggests for their energy compaction on natural images.
enum class BlockBasis { kPrincipal, kWalshHadamard };

struct BlockSynthesisOptions {
  int width = 512, height = 512;  // output texels
  int block = 30;                 // block side (the paper: 30 x 30)
  int overlap = 0;                // texels shared with the neighbours; 0: block / 6
  // Candidates whose neighbourhood distance is within (1 + tolerance) of the best are admitted
  // (Efros & Freeman draw one at random, tolerance 0.1; 0.5 here, measured on 20 photographs:
  // docs/synthesis.md). 0 admits only the best.
  double tolerance = 0.5;
  // Among the admitted blocks, the least used first: how many output texels already come from the
  // block's sample texels. Blocks drawn at random favour the sample's centre (a border texel lies in
  // one block position, a central one in `block`) and the blocks that match anything (bland ones),
  // so the output's histograms drifted from the sample's. Off: a random order.
  bool balance_usage = true;
  // In that order, the first block whose boundary cuts leave a mean step of at most this x the
  // sample's mean neighbour step; if none does, the one whose cuts err least. 0: the first.
  double seam_limit = 1.2;
  // Candidates within this many texels (in both axes) of the sample position that continues the
  // left or the upper neighbour's block are left out: the continuation matches its overlap
  // exactly (distance 0), so with it a tolerance relative to the best admits nothing else and the
  // output copies the sample verbatim until its edge. 0 keeps them.
  int continuation_exclusion = 0;
  int projections = 8;            // basis vectors of the lower bounds
  BlockBasis basis = BlockBasis::kPrincipal;
  BlockSearch search = BlockSearch::kRejection;
  uint32_t seed = 1;
  int num_threads = -1;
  Status Check(int sample_width, int sample_height) const;
  int EffectiveOverlap() const { return overlap > 0 ? overlap : std::max(1, block / 6); }
};

struct BlockSynthesisReport {
  int blocks = 0, overlap = 0;
  long candidates_per_query = 0;  // sample positions a block may come from
  long queries = 0;               // blocks chosen by their neighbourhood (all but the first)
  long full_distances = 0;        // neighbourhood distances computed in full
  double rejected_fraction = 0;   // of candidates, over all queries, rejected by their bound alone
  double mean_cut_error = 0;      // mean error per texel along the boundary cuts (feature units)
  double seconds_basis = 0, seconds_search = 0, seconds_cut = 0, seconds = 0;
};

// Block synthesis of `sample_features` (one vector per texel) into a map of options.width x
// height. `built`, if given, receives the features placed (what applying the map to the sample
// reproduces bit for bit).
StatusOr<SynthMap> BlockSynthesis(const Image& sample_features, const BlockSynthesisOptions& options,
                                  BlockSynthesisReport* report, const ProgressFn& progress = nullptr, Image* built = nullptr);

// One search, exposed for tests and benchmarks: the candidates (sample positions, row-major
// index y * (sample width - block + 1) + x) whose neighbourhood distance to `output`'s at block
// position (x0, y0) (neighbourhood: left strip if x0 > 0, top strip if y0 > 0) is within (1 +
// tolerance) of the best, in index order, with their distances; candidates an `excluded` predicate
// names take no part.
struct BlockCandidate {
  long index = 0;
  double distance = 0;
};
class BlockSearchIndex;
struct BlockSearchResult {
  std::vector<BlockCandidate> candidates;
  long full_distances = 0, rejected = 0;
};

class BlockSearcher {
 public:
  BlockSearcher(const Image& sample_features, int block, int overlap, int projections, int num_threads,
                BlockBasis basis = BlockBasis::kPrincipal);
  ~BlockSearcher();
  BlockSearcher(const BlockSearcher&) = delete;
  BlockSearcher& operator=(const BlockSearcher&) = delete;
  long candidate_count() const;
  int candidate_columns() const;
  // Candidates for which `excluded(x, y)` (sample position) is true are never returned.
  BlockSearchResult Search(const Image& output, int x0, int y0, double tolerance, BlockSearch search,
                           const std::function<bool(int, int)>& excluded = nullptr) const;
  double seconds_basis() const { return seconds_basis_; }

 private:
  const Image& sample_;
  int block_, num_threads_;  // the overlap shapes the indexes only
  std::unique_ptr<BlockSearchIndex> indexes_[3];  // left strip, top strip, both
  double seconds_basis_ = 0;
};

}  // namespace mesocap
