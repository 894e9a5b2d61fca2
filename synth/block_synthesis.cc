#include "synth/block_synthesis.h"

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>

#include "core/parallel.h"
#include "core/progress.h"
#include "core/text_format.h"
#include "synth/feature_distance.h"
#include "synth/graphcut_fit.h"
#include "synth/usage_table.h"

namespace mesocap {
namespace {

enum Shape { kLeft = 0, kTop = 1, kBoth = 2 };

// The block texels a neighbourhood of `shape` compares (row-major): the left strip of `overlap`
// columns, the top strip of `overlap` rows, or both.
std::vector<Eigen::Vector2i> ShapeOffsets(Shape shape, int block, int overlap) {
  std::vector<Eigen::Vector2i> offsets;
  for (int dy = 0; dy < block; ++dy)
    for (int dx = 0; dx < block; ++dx) {
      const bool left = dx < overlap, top = dy < overlap;
      if ((shape == kLeft && left) || (shape == kTop && top) || (shape == kBoth && (left || top)))
        offsets.emplace_back(dx, dy);
    }
  return offsets;
}

}  // namespace

// The lower-bound machinery of one neighbourhood shape: an orthonormal basis of the unfolded
// neighbourhood vectors and every candidate's projection onto it.
class BlockSearchIndex {
 public:
  std::vector<Eigen::Vector2i> offsets;
  int features = 0;
  Eigen::MatrixXd basis;       // k x q, orthonormal columns
  Eigen::MatrixXd projection;  // q x candidates

  long dimension() const { return long(offsets.size()) * features; }

  // The unfolded neighbourhood of the block whose top-left texel is (x0, y0) in `image`.
  void Gather(const Image& image, int x0, int y0, double* out) const {
    for (const Eigen::Vector2i& o : offsets) {
      const float* p = image.pixel(x0 + o.x(), y0 + o.y());
      for (int f = 0; f < features; ++f) *out++ = p[f];
    }
  }
};

namespace {

// The first `q` principal directions (uncentred) of the neighbourhoods of up to 2048 evenly
// spread candidates: a randomized SVD (Halko et al.: 8 extra columns, 2 power iterations). Any
// orthonormal basis keeps the bounds exact; this one makes them tight.
Eigen::MatrixXd NeighbourhoodBasis(const BlockSearchIndex& index, const Image& sample, int columns, long candidates, int q) {
  const long k = index.dimension();
  const long rows = std::min<long>(candidates, 2048);
  Eigen::MatrixXd a(rows, k);
  for (long r = 0; r < rows; ++r) {
    const long c = r * candidates / rows;
    Eigen::VectorXd v(k);
    index.Gather(sample, int(c % columns), int(c / columns), v.data());
    a.row(r) = v.transpose();
  }
  const int width = int(std::min<long>(k, q + 8));
  std::mt19937 rng(12345);
  std::normal_distribution<double> gauss;
  Eigen::MatrixXd omega(k, width);
  for (long i = 0; i < omega.size(); ++i) omega.data()[i] = gauss(rng);
  Eigen::MatrixXd y = a * omega;
  for (int pass = 0; pass < 2; ++pass) {
    y = Eigen::HouseholderQR<Eigen::MatrixXd>(y).householderQ() * Eigen::MatrixXd::Identity(rows, width);
    y = a * (a.transpose() * y);
  }
  const Eigen::MatrixXd range = Eigen::HouseholderQR<Eigen::MatrixXd>(y).householderQ() * Eigen::MatrixXd::Identity(rows, width);
  const Eigen::MatrixXd b = range.transpose() * a;  // width x k
  Eigen::BDCSVD<Eigen::MatrixXd> svd(b, Eigen::ComputeThinV);
  const Eigen::MatrixXd v = svd.matrixV().leftCols(std::min(q, width));
  // Orthonormal to double precision, whatever the SVD left.
  return Eigen::HouseholderQR<Eigen::MatrixXd>(v).householderQ() * Eigen::MatrixXd::Identity(k, v.cols());
}

// The first `q` Walsh functions in sequency order on `k` entries (a vector zero-padded to the next
// power of two N): row i is the natural-order Hadamard row bitreverse(gray(i)), scaled by
// 1/sqrt(N). Truncated to k entries the rows are not orthonormal in R^k, but the padded vector's
// projections on the full rows still sum to at most its squared norm: the bounds stay exact.
Eigen::MatrixXd WalshBasis(long k, int q) {
  int bits = 0;
  while ((long(1) << bits) < k) ++bits;
  const double scale = 1.0 / std::sqrt(double(long(1) << bits));
  Eigen::MatrixXd basis(k, std::min<long>(q, long(1) << bits));
  for (long i = 0; i < basis.cols(); ++i) {
    const long gray = i ^ (i >> 1);
    long row = 0;
    for (int b = 0; b < bits; ++b)
      if (gray & (long(1) << b)) row |= long(1) << (bits - 1 - b);
    for (long c = 0; c < k; ++c) basis(c, i) = __builtin_popcountl(row & c) % 2 ? -scale : scale;
  }
  return basis;
}

// Squared L2 distance between the query's neighbourhood and candidate (x, y)'s, summed in a fixed
// order; stops early (returning a value above `stop`) once the sum exceeds `stop`.
double NeighbourhoodDistance(const BlockSearchIndex& index, const Image& sample, const double* query, int x, int y,
                             double stop) {
  double sum = 0;
  const int f = index.features;
  for (size_t t = 0; t < index.offsets.size(); ++t) {
    const float* p = sample.pixel(x + index.offsets[t].x(), y + index.offsets[t].y());
    const double* q = query + t * f;
    for (int i = 0; i < f; ++i) {
      const double d = q[i] - double(p[i]);
      sum += d * d;
    }
    if (sum > stop) return sum;
  }
  return sum;
}

// The candidates within (1 + tolerance) of the best distance, in index order.
std::vector<BlockCandidate> WithinTolerance(std::vector<BlockCandidate> found, double tolerance) {
  double best = std::numeric_limits<double>::infinity();
  for (const BlockCandidate& c : found) best = std::min(best, c.distance);
  const double limit = best * (1 + tolerance);
  found.erase(std::remove_if(found.begin(), found.end(), [&](const BlockCandidate& c) { return c.distance > limit; }),
              found.end());
  std::sort(found.begin(), found.end(), [](const BlockCandidate& a, const BlockCandidate& b) { return a.index < b.index; });
  return found;
}

}  // namespace

Status BlockSynthesisOptions::Check(int sample_width, int sample_height) const {
  if (width < 1 || height < 1) return Status::Error("the output size must be at least 1 x 1");
  if (block < 2) return Status::Error("the block must be at least 2 texels");
  if (overlap < 0 || EffectiveOverlap() >= block)
    return Status::Error(Format("the overlap (%d) must be smaller than the block (%d)", EffectiveOverlap(), block));
  if (sample_width < block || sample_height < block)
    return Status::Error(Format("the sample (%dx%d) is smaller than a block (%d x %d): use a smaller --block", sample_width,
                                sample_height, block, block));
  if (!(tolerance >= 0)) return Status::Error("the tolerance must be at least 0");
  if (!(seam_limit >= 0)) return Status::Error("the seam limit must be at least 0");
  if (projections < 1) return Status::Error("at least one projection is needed for the lower bounds");
  return Status::Ok();
}

BlockSearcher::BlockSearcher(const Image& sample_features, int block, int overlap, int projections, int num_threads,
                             BlockBasis basis)
    : sample_(sample_features), block_(block), num_threads_(num_threads) {
  const auto start = std::chrono::steady_clock::now();
  const int columns = candidate_columns();
  const long candidates = candidate_count();
  for (Shape shape : {kLeft, kTop, kBoth}) {
    auto index = std::make_unique<BlockSearchIndex>();
    index->offsets = ShapeOffsets(shape, block, overlap);
    index->features = sample_features.channels();
    index->basis = basis == BlockBasis::kPrincipal ? NeighbourhoodBasis(*index, sample_features, columns, candidates, projections)
                                                   : WalshBasis(index->dimension(), projections);
    index->projection.resize(index->basis.cols(), candidates);
    const BlockSearchIndex& ix = *index;
    Eigen::MatrixXd& projection = index->projection;
    ParallelFor(
        0, int(candidates),
        [&](int c) {
          thread_local Eigen::VectorXd v;
          v.resize(ix.dimension());
          ix.Gather(sample_, c % columns, c / columns, v.data());
          projection.col(c) = ix.basis.transpose() * v;
        },
        num_threads);
    indexes_[shape] = std::move(index);
  }
  seconds_basis_ = SecondsSince(start);
}

BlockSearcher::~BlockSearcher() = default;

int BlockSearcher::candidate_columns() const { return sample_.width() - block_ + 1; }
long BlockSearcher::candidate_count() const { return long(candidate_columns()) * (sample_.height() - block_ + 1); }

BlockSearchResult BlockSearcher::Search(const Image& output, int x0, int y0, double tolerance, BlockSearch search,
                                        const std::function<bool(int, int)>& excluded) const {
  MESOCAP_CHECK(x0 > 0 || y0 > 0, "the first block has no neighbourhood to search with");
  const BlockSearchIndex& index = *indexes_[x0 > 0 && y0 > 0 ? kBoth : (x0 > 0 ? kLeft : kTop)];
  const int columns = candidate_columns();
  const long candidates = candidate_count();
  Eigen::VectorXd query(index.dimension());
  index.Gather(output, x0, y0, query.data());
  BlockSearchResult result;
  const double inf = std::numeric_limits<double>::infinity();
  if (search == BlockSearch::kBruteForce) {
    std::vector<double> distance(static_cast<size_t>(candidates));
    ParallelFor(
        0, int(candidates),
        [&](int c) { distance[size_t(c)] = NeighbourhoodDistance(index, sample_, query.data(), c % columns, c / columns, inf); },
        num_threads_);
    std::vector<BlockCandidate> all;
    for (long c = 0; c < candidates; ++c)
      if (!excluded || !excluded(int(c % columns), int(c / columns))) all.push_back({c, distance[size_t(c)]});
    result.full_distances = candidates;
    result.candidates = WithinTolerance(std::move(all), tolerance);
    return result;
  }
  // Lower bounds from the projections, then full distances in order of the bound until the bound
  // passes the threshold: every candidate left unevaluated has a bound, hence a distance, above it.
  const Eigen::VectorXd projected = index.basis.transpose() * query;
  std::vector<double> bound(static_cast<size_t>(candidates));
  ParallelFor(
      0, int(candidates), [&](int c) { bound[size_t(c)] = (index.projection.col(c) - projected).squaredNorm(); },
      num_threads_);
  // Candidates in increasing order of their bound (ties by index), popped from a heap: the search
  // stops after a few, and sorting all of them took longer than the search.
  std::vector<long> heap(static_cast<size_t>(candidates));
  std::iota(heap.begin(), heap.end(), 0L);
  const auto later = [&](long a, long b) {
    return bound[size_t(a)] > bound[size_t(b)] || (bound[size_t(a)] == bound[size_t(b)] && a > b);
  };
  std::make_heap(heap.begin(), heap.end(), later);
  std::vector<BlockCandidate> found;
  double best = inf, threshold = inf;
  for (auto heap_end = heap.end(); heap_end != heap.begin();) {
    std::pop_heap(heap.begin(), heap_end, later);
    const long c = *--heap_end;
    // The bound is exact up to rounding (relative 1e-12 in doubles): a small margin keeps a
    // candidate whose distance equals the threshold.
    if (bound[size_t(c)] * (1 - 1e-9) > threshold) break;
    if (excluded && excluded(int(c % columns), int(c / columns))) continue;
    const double d = NeighbourhoodDistance(index, sample_, query.data(), int(c % columns), int(c / columns), threshold);
    ++result.full_distances;
    if (d > threshold) continue;
    found.push_back({c, d});
    if (d < best) best = d, threshold = best * (1 + tolerance);
  }
  result.rejected = candidates - result.full_distances;
  result.candidates = WithinTolerance(std::move(found), tolerance);
  return result;
}

namespace {

// Minimum-error boundary cut through an overlap (Efros & Freeman): along each of `length` lines,
// the position in [0, width) of the first new texel, found by dynamic programming, moving at most
// one position between lines. `error(line, position)` is the cost of cutting there and
// `shift(line, from, to)` the cost of the path moving between lines (the steps it leaves across).
std::vector<int> MinimumErrorCut(int length, int width, const std::function<double(int, int)>& error,
                                 const std::function<double(int, int, int)>& shift, double* cut_error) {
  std::vector<double> cost(size_t(length) * width);
  std::vector<int> from(size_t(length) * width, 0);
  for (int p = 0; p < width; ++p) cost[size_t(p)] = error(0, p);
  for (int l = 1; l < length; ++l)
    for (int p = 0; p < width; ++p) {
      double best_cost = std::numeric_limits<double>::infinity();
      int best = p;
      for (int q = std::max(0, p - 1); q <= std::min(width - 1, p + 1); ++q) {
        const double c = cost[size_t(l - 1) * width + q] + (q == p ? 0.0 : shift(l, q, p));
        if (c < best_cost) best_cost = c, best = q;
      }
      cost[size_t(l) * width + p] = error(l, p) + best_cost;
      from[size_t(l) * width + p] = best;
    }
  std::vector<int> path(static_cast<size_t>(length));
  int p = int(std::min_element(cost.end() - width, cost.end()) - (cost.end() - width));
  *cut_error = cost[size_t(length - 1) * width + p] / length;
  for (int l = length - 1; l >= 0; --l) {
    path[size_t(l)] = p;
    p = from[size_t(l) * width + p];
  }
  return path;
}

double StepError(const Image& a, int ax, int ay, const Image& b, int bx, int by) {
  return FeatureDistance(a.pixel(ax, ay), b.pixel(bx, by), a.channels());
}

// Where sample block (sx, sy) placed at canvas (x0, y0) takes over: it starts right of the vertical
// cut (through the left overlap, if `left`) and below the horizontal one (the top overlap, if `top`).
struct BlockCuts {
  std::vector<int> column, row;  // per block row, the first new column; per block column, the first new row
  double worst = 0;              // the larger of the two cuts' mean error per line
  double sum = 0;                // the cuts' mean errors summed
  int count = 0;
};

BlockCuts CutBlock(const Image& canvas, const Image& sample, int x0, int y0, int sx, int sy, int block, int overlap, bool left,
                   bool top) {
  BlockCuts cuts;
  cuts.column.assign(size_t(block), 0), cuts.row.assign(size_t(block), 0);
  // A cut along lines (rows for the vertical cut, columns for the horizontal one): `at(line,
  // position)` is the block offset. Cutting at p leaves old p-1 next to new p; moving from q to q+1
  // between lines leaves new q on the line before next to old q on this one, and from q to q-1 old
  // q-1 on the line before next to new q-1 on this one.
  const auto cut_along = [&](bool rows) {
    const auto at = [rows](int line, int position) { return rows ? std::pair{position, line} : std::pair{line, position}; };
    const auto step = [&](std::pair<int, int> old_texel, std::pair<int, int> new_texel) {
      return StepError(canvas, x0 + old_texel.first, y0 + old_texel.second, sample, sx + new_texel.first, sy + new_texel.second);
    };
    double error = 0;
    std::vector<int> path = MinimumErrorCut(
        block, overlap, [&](int l, int p) { return step(at(l, p - 1), at(l, p)); },
        [&](int l, int q, int p) { return p > q ? step(at(l, q), at(l - 1, q)) : step(at(l - 1, p), at(l, p)); }, &error);
    cuts.worst = std::max(cuts.worst, error), cuts.sum += error, ++cuts.count;
    return path;
  };
  if (left) cuts.column = cut_along(true);
  if (top) cuts.row = cut_along(false);
  return cuts;
}

// The admitted candidates in the order they are tried: at random, then (with `usage`) the least
// used blocks first.
std::vector<long> TryOrder(const std::vector<BlockCandidate>& admitted, const UsageTable* usage, int columns, int block,
                           std::mt19937& rng) {
  std::vector<long> order;
  for (const BlockCandidate& c : admitted) order.push_back(c.index);
  std::shuffle(order.begin(), order.end(), rng);
  if (!usage) return order;
  std::vector<std::pair<double, long>> keyed;
  for (long c : order) keyed.emplace_back(usage->Block(int(c % columns), int(c / columns), block), c);
  std::stable_sort(keyed.begin(), keyed.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  for (size_t i = 0; i < keyed.size(); ++i) order[i] = keyed[i].second;
  return order;
}

}  // namespace

StatusOr<SynthMap> BlockSynthesis(const Image& sample, const BlockSynthesisOptions& options, BlockSynthesisReport* report,
                                  const ProgressFn& progress, Image* built) {
  MESOCAP_RETURN_IF_ERROR(options.Check(sample.width(), sample.height()));
  const auto start = std::chrono::steady_clock::now();
  const int block = options.block, overlap = options.EffectiveOverlap(), step = block - overlap;
  const int blocks_x = std::max(1, (options.width - overlap + step - 1) / step);
  const int blocks_y = std::max(1, (options.height - overlap + step - 1) / step);
  const int canvas_w = blocks_x * step + overlap, canvas_h = blocks_y * step + overlap;
  BlockSearcher searcher(sample, block, overlap, options.projections, options.num_threads, options.basis);
  BlockSynthesisReport r;
  r.overlap = overlap;
  r.candidates_per_query = searcher.candidate_count();
  r.seconds_basis = searcher.seconds_basis();
  Image canvas(canvas_w, canvas_h, sample.channels());
  SynthMap full(canvas_w, canvas_h, sample.width(), sample.height(), "ptm-block");
  std::mt19937 rng(options.seed);
  long rejected = 0;
  double cut_error_sum = 0;
  int cut_count = 0;
  const int columns = searcher.candidate_columns();
  const double sample_step = MeanNeighbourStep(sample);
  // Each block's sample position, for the continuation rule.
  std::vector<Eigen::Vector2i> source(size_t(blocks_x) * blocks_y, Eigen::Vector2i(-1, -1));
  SampleUsage usage(sample.width(), sample.height());
  for (int by = 0; by < blocks_y; ++by) {
    for (int bx = 0; bx < blocks_x; ++bx) {
      const int x0 = bx * step, y0 = by * step;
      std::vector<Eigen::Vector2i> continuations;
      if (bx > 0) continuations.push_back(source[size_t(by) * blocks_x + bx - 1] + Eigen::Vector2i(step, 0));
      if (by > 0) continuations.push_back(source[size_t(by - 1) * blocks_x + bx] + Eigen::Vector2i(0, step));
      const int reach = options.continuation_exclusion;
      std::function<bool(int, int)> continues;
      if (reach > 0)
        continues = [&continuations, reach](int x, int y) {
          for (const Eigen::Vector2i& c : continuations)
            if (std::abs(x - c.x()) < reach && std::abs(y - c.y()) < reach) return true;
          return false;
        };
      long chosen = 0;
      BlockCuts cuts = CutBlock(canvas, sample, x0, y0, 0, 0, block, overlap, false, false);  // none: the first block
      if (bx == 0 && by == 0) {
        chosen = std::uniform_int_distribution<long>(0, searcher.candidate_count() - 1)(rng);
      } else {
        const auto search_start = std::chrono::steady_clock::now();
        BlockSearchResult found = searcher.Search(canvas, x0, y0, options.tolerance, options.search, continues);
        if (found.candidates.empty())  // a sample too small to hold anything but continuations
          found = searcher.Search(canvas, x0, y0, options.tolerance, options.search);
        ++r.queries;
        r.full_distances += found.full_distances;
        rejected += found.rejected;
        r.seconds_search += SecondsSince(search_start);
        const auto choice_start = std::chrono::steady_clock::now();
        const std::vector<long> order =
            TryOrder(found.candidates, options.balance_usage ? &usage.Table() : nullptr, columns, block, rng);
        // The first in that order whose cuts stay within the seam limit, else the one whose cuts err least.
        double least = std::numeric_limits<double>::infinity();
        for (long c : order) {
          BlockCuts trial = CutBlock(canvas, sample, x0, y0, int(c % columns), int(c / columns), block, overlap, bx > 0, by > 0);
          if (trial.worst < least) least = trial.worst, chosen = c, cuts = std::move(trial);
          if (options.seam_limit <= 0 || least <= options.seam_limit * sample_step) break;
        }
        r.seconds_cut += SecondsSince(choice_start);
      }
      const int sx = int(chosen % columns), sy = int(chosen / columns);
      source[size_t(by) * blocks_x + bx] = {sx, sy};
      cut_error_sum += cuts.sum, cut_count += cuts.count;
      const int32_t id = by * blocks_x + bx;
      for (int dy = 0; dy < block; ++dy)
        for (int dx = 0; dx < block; ++dx) {
          if (dx < cuts.column[size_t(dy)] || dy < cuts.row[size_t(dx)]) continue;
          std::copy_n(sample.pixel(sx + dx, sy + dy), sample.channels(), canvas.pixel(x0 + dx, y0 + dy));
          const bool in_output = x0 + dx < options.width && y0 + dy < options.height;
          if (in_output && full.filled(x0 + dx, y0 + dy)) usage.Add(full.SourceTexel(x0 + dx, y0 + dy), -1);  // cut away
          full.Set(x0 + dx, y0 + dy, float(sx + dx) + 0.5f, float(sy + dy) + 0.5f, 0, id);
          if (in_output) usage.Add({sx + dx, sy + dy}, 1);
        }
      ++r.blocks;
    }
    if (progress) progress(by + 1, blocks_y, "blocks");
  }
  SynthMap map(options.width, options.height, sample.width(), sample.height(), "ptm-block");
  for (int y = 0; y < options.height; ++y)
    for (int x = 0; x < options.width; ++x) {
      const size_t i = full.index(x, y);
      map.Set(x, y, full.source_x[i], full.source_y[i], 0, full.patch[i]);
    }
  if (built) {
    *built = Image(options.width, options.height, sample.channels());
    for (int y = 0; y < options.height; ++y)
      std::copy_n(canvas.row(y), size_t(options.width) * sample.channels(), built->row(y));
  }
  r.rejected_fraction = r.queries ? double(rejected) / (double(r.queries) * r.candidates_per_query) : 0;
  r.mean_cut_error = cut_count ? cut_error_sum / cut_count : 0;
  r.seconds = SecondsSince(start);
  if (report) *report = r;
  return map;
}

}  // namespace mesocap
