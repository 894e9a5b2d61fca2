#include "synth/texton_sample.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>

#include <Eigen/Eigenvalues>

#include "core/cancel.h"
#include "core/parallel.h"

namespace mesocap {
namespace {

constexpr int kEmbeddingDimensions = 8;  // texton coordinates per slot in the neighbourhood summary
constexpr int kSummaryDimensions = 12;   // principal components of the summary (L&H 2006 keep 8 of theirs)
constexpr int kRerankFactor = 4;         // summary-nearest texels re-ranked by the exact distance, per list entry
constexpr int kListBlock = 64;           // texels whose lists one task builds
constexpr int kSummaryRows = 8;          // texels whose summary distances are summed together
constexpr int kScanStretch = 32;         // candidates whose least summary distance is checked at once
constexpr int kSparseSpacing = 2;        // levels this spaced draw their lists from every other row and column
constexpr int kPcaRows = 4096;           // texels the summaries' principal components are found from


// Keeps the `size` smallest (distance, texel) pairs seen.
class Nearest {
 public:
  explicit Nearest(int size) : size_(size) {}
  float bound() const { return int(heap_.size()) < size_ ? kTextonInfinity : heap_.front().first; }
  void Offer(float d, int32_t t) {
    if (size_ <= 0) return;
    const std::pair<float, int32_t> item(d, t);
    if (int(heap_.size()) < size_) {
      heap_.push_back(item), std::push_heap(heap_.begin(), heap_.end());
    } else if (item < heap_.front()) {
      std::pop_heap(heap_.begin(), heap_.end()), heap_.back() = item, std::push_heap(heap_.begin(), heap_.end());
    }
  }
  std::vector<std::pair<float, int32_t>> Sorted() {
    std::sort_heap(heap_.begin(), heap_.end());
    return heap_;
  }
  void Clear() { heap_.clear(); }

 private:
  int size_;
  std::vector<std::pair<float, int32_t>> heap_;
};

// Per sample texel, a short summary of its neighbourhood whose squared distances approximate
// the Gamma distance: each slot's texton as coordinates from Gamma's leading eigenvectors
// (Gamma = T T^T), concatenated over slots and reduced to their principal components. Stored
// component-major (summary[k * count + i]). Plain loops in a fixed order, not matrix products:
// a product's rounding depends on how its operands happen to be aligned in memory, and a list
// built on a near-tie would then differ from one run to the next.
std::vector<float> NeighbourhoodSummaries(const SampleLevel& s, int* dimensions) {
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(s.level->gamma);
  const int n = int(s.level->gamma.rows()), e = std::min(kEmbeddingDimensions, n);
  Eigen::MatrixXd embedding(n, e);  // the leading eigenvalues come last
  for (int j = 0; j < e; ++j)
    embedding.col(j) = eigen.eigenvectors().col(n - 1 - j) * std::sqrt(std::max(0.0, eigen.eigenvalues()(n - 1 - j)));
  const int S = s.slot_count(), D = S * e, count = s.texels();
  auto row = [&](int i, std::vector<double>& x) {  // the concatenated coordinates of texel i
    const uint16_t* v = s.vector(i);
    for (int j = 0; j < S; ++j)
      for (int c = 0; c < e; ++c) x[size_t(j) * e + c] = embedding(v[j] == s.outside ? n - 1 : v[j], c);  // outside: the mean
  };
  // Mean and covariance from at most kPcaRows texels, evenly spaced.
  const int step = std::max(1, count / kPcaRows);
  std::vector<double> x(D), mean(D, 0);
  Eigen::MatrixXd covariance = Eigen::MatrixXd::Zero(D, D);
  int rows = 0;
  for (int i = 0; i < count; i += step, ++rows) {
    row(i, x);
    for (int a = 0; a < D; ++a) mean[a] += x[a];
  }
  for (double& m : mean) m /= rows;
  for (int i = 0; i < count; i += step) {
    row(i, x);
    for (int a = 0; a < D; ++a) x[a] -= mean[a];
    for (int a = 0; a < D; ++a)
      for (int b = 0; b <= a; ++b) covariance(a, b) += x[a] * x[b];
  }
  covariance = covariance.selfadjointView<Eigen::Lower>();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> pca(covariance);
  const int d = std::min(kSummaryDimensions, D);
  *dimensions = d;
  std::vector<float> summary(size_t(d) * count);
  for (int i = 0; i < count; ++i) {
    row(i, x);
    for (int k = 0; k < d; ++k) {
      double v = 0;
      for (int a = 0; a < D; ++a) v += (x[a] - mean[a]) * pca.eigenvectors()(a, D - 1 - k);
      summary[size_t(k) * count + i] = float(v);
    }
  }
  return summary;
}

// The summaries of a level's texels (component-major, `dimensions` components) and of the
// candidates their lists are drawn from: every texel, or at levels spaced kSparseSpacing or more,
// those on even rows and columns (a level blurred over its spacing varies little between
// neighbours, and texels within the spacing are left out of each other's lists anyway).
struct Summaries {
  std::vector<float> texels, candidates;
  std::vector<int32_t> candidate_texel;  // candidate -> texel
  int dimensions = 0, count = 0, candidate_count = 0;
};

// Squared summary distances from texels first .. first + kSummaryRows - 1 to every candidate, into
// distances[r * candidates + j], and the least of each stretch of kScanStretch candidates into
// least[r * stretches + k]: four candidates at a time, each sum kept in a register over the
// components in the same order (the lists do not depend on the thread count or the memory's
// alignment; GCC's vector extensions, plain SSE2 on any x86-64). Texels past the last are summed
// against zeros and never read.
void SummaryDistances(const Summaries& y, int first, float* distances, float* least) {
  using Floats = float __attribute__((vector_size(16)));
  constexpr int kLanes = 4;
  const int m = y.candidate_count, d = y.dimensions;
  float own[kSummaryRows][kSummaryDimensions] = {};
  for (int r = 0; r < kSummaryRows && first + r < y.count; ++r)
    for (int c = 0; c < d; ++c) own[r][c] = y.texels[size_t(c) * y.count + first + r];
  const int stretches = (m + kScanStretch - 1) / kScanStretch;
  std::fill_n(least, size_t(kSummaryRows) * stretches, std::numeric_limits<float>::infinity());
  auto keep = [&](int r, int j, float sum) {
    distances[size_t(r) * m + j] = sum;
    float& l = least[size_t(r) * stretches + j / kScanStretch];
    l = std::min(l, sum);
  };
  int j = 0;
  for (; j + kLanes <= m; j += kLanes) {
    Floats sum[kSummaryRows];
    for (int r = 0; r < kSummaryRows; ++r) sum[r] = Floats{};
    for (int c = 0; c < d; ++c) {
      Floats candidate;
      std::memcpy(&candidate, y.candidates.data() + size_t(c) * m + j, sizeof candidate);
      for (int r = 0; r < kSummaryRows; ++r) {
        const Floats diff = candidate - own[r][c];
        sum[r] += diff * diff;
      }
    }
    for (int r = 0; r < kSummaryRows; ++r)
      for (int l = 0; l < kLanes; ++l) keep(r, j + l, sum[r][l]);
  }
  for (; j < m; ++j)  // the last m % kLanes candidates
    for (int r = 0; r < kSummaryRows; ++r) {
      float sum = 0;
      for (int c = 0; c < d; ++c) {
        const float diff = y.candidates[size_t(c) * m + j] - own[r][c];
        sum += diff * diff;
      }
      keep(r, j, sum);
    }
}

}  // namespace

// The n x n template around a texel without the texel itself, nearest offsets first: a distance
// summed in this order passes a candidate's bound sooner (near texels differ most).
std::vector<Offset> Square(int n) {
  std::vector<Offset> v;
  for (int dy = -(n / 2); dy <= n / 2; ++dy)
    for (int dx = -(n / 2); dx <= n / 2; ++dx)
      if (dx || dy) v.push_back({dx, dy});
  std::stable_sort(v.begin(), v.end(), [](const Offset& a, const Offset& b) {
    return a.dx * a.dx + a.dy * a.dy < b.dx * b.dx + b.dy * b.dy;
  });
  return v;
}

// A texel near the border is a candidate like any other, its slots beyond the sample costed at
// kOutsideCost x the typical distance (the mean over pairs of the sample's texels). Candidates
// restricted to whole neighbourhoods left a rim of a quarter of the sample unused at coarse levels
// and the output's histograms drifted toward the sample's centre's: on the 20 photographs the
// subband statistics were 1.74x random tiling's (geometric mean), 1.32x with every texel; random
// tiling from the centre alone scores 1.8-2.5x. Half the typical distance (the distance to the
// mean, as Tong's default texton) measured best: 1 gave 1.47x, 0.25 more repeats (7.6%), 0 2.2x.
const double kOutsideCost = 0.5;

SampleLevel MakeSampleLevel(const TextonLevel& level, int n) {
  SampleLevel s;
  s.level = &level;
  s.spacing = level.spacing;
  const int labels = level.textons + 1;
  const std::vector<float> table = TextonDistances(level);
  std::vector<double> share(labels, 0);
  for (int32_t l : level.labels) share[l] += 1.0 / double(level.labels.size());
  double typical = 0;
  for (int i = 0; i < labels; ++i)
    for (int j = 0; j < labels; ++j) typical += share[i] * share[j] * table[size_t(i) * labels + j];
  s.stride = labels + 1, s.outside = labels;
  s.distances.assign(size_t(s.stride) * s.stride, float(kOutsideCost * typical));  // `outside` both ways
  for (int i = 0; i < labels; ++i) std::copy_n(table.data() + size_t(i) * labels, labels, s.distances.data() + size_t(i) * s.stride);
  s.distances.back() = 0;  // two slots beyond the sample (sample texels' lists compare two such vectors)
  s.slots = Square(n);
  const int W = level.width, H = level.height, S = s.slot_count();
  s.vectors.resize(size_t(W) * H * S);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      uint16_t* v = s.vectors.data() + (size_t(y) * W + x) * S;
      for (const Offset& o : s.slots) {
        const int xx = x + s.spacing * o.dx, yy = y + s.spacing * o.dy;
        *v++ = uint16_t(s.Inside(xx, yy) ? level.label(xx, yy) : s.outside);
      }
    }
  return s;
}

Query SampleQuery(const SampleLevel& s, int t) {
  Query q;
  const uint16_t* v = s.vector(t);
  for (int j = 0; j < s.slot_count(); ++j) q.rows.push_back(s.Row(v[j]));
  return q;
}

// The similar-texel list of every sample texel: the texel itself, then the k - 1 nearest others
// by the exact distance among kRerankFactor x as many nearest by summary, none within the level's
// spacing (at least 2) of the texel: on a blurred level those are near copies of it, and on the
// finest its direct neighbours, which would stretch it across the output.
// Returns false when cancelled (core/cancel.h: each block checks, so Ctrl-C stops it within a block).
bool BuildNearestLists(SampleLevel& s, int k, int num_threads) {
  const int count = s.texels();
  s.list_length = std::max(1, std::min(k, count));
  s.nearest.resize(size_t(count) * s.list_length);
  if (s.list_length == 1) {
    std::iota(s.nearest.begin(), s.nearest.end(), 0);
    return true;
  }
  Summaries y;
  y.texels = NeighbourhoodSummaries(s, &y.dimensions);
  y.count = count;
  const int W = s.width(), blocks = (count + kListBlock - 1) / kListBlock, exclusion = std::max(2, s.spacing);
  for (int32_t t = 0; t < count; ++t)
    if (s.spacing < kSparseSpacing || (t % W % 2 == 0 && t / W % 2 == 0)) y.candidate_texel.push_back(t);
  y.candidate_count = int(y.candidate_texel.size());
  const int m = y.candidate_count;
  y.candidates.resize(size_t(y.dimensions) * m);
  for (int c = 0; c < y.dimensions; ++c)
    for (int j = 0; j < m; ++j) y.candidates[size_t(c) * m + j] = y.texels[size_t(c) * count + y.candidate_texel[j]];
  ParallelFor(0, blocks, [&](int b) {
    if (CancelRequested()) return;
    const int stretches = (m + kScanStretch - 1) / kScanStretch;
    std::vector<float> distances(size_t(kSummaryRows) * m), least(size_t(kSummaryRows) * stretches);
    Nearest summary(kRerankFactor * (s.list_length - 1)), exact(s.list_length - 1);
    for (int i = b * kListBlock; i < std::min(count, (b + 1) * kListBlock); ++i) {
      const int row = (i - b * kListBlock) % kSummaryRows;
      if (row == 0) SummaryDistances(y, i, distances.data(), least.data());
      const float* distance = distances.data() + size_t(row) * m;
      const float* stretch_least = least.data() + size_t(row) * stretches;
      const int32_t t = i;
      const int tx = t % W, ty = t / W;
      summary.Clear(), exact.Clear();
      for (int j0 = 0; j0 < m; j0 += kScanStretch) {  // most stretches hold no candidate within the bound
        if (stretch_least[j0 / kScanStretch] >= summary.bound()) continue;
        for (int j = j0; j < std::min(m, j0 + kScanStretch); ++j) {
          if (distance[j] >= summary.bound()) continue;
          const int32_t c = y.candidate_texel[j];
          if (std::abs(c % W - tx) < exclusion && std::abs(c / W - ty) < exclusion) continue;
          summary.Offer(distance[j], c);
        }
      }
      const Query q = SampleQuery(s, t);
      for (const auto& [dist, c] : summary.Sorted()) exact.Offer(q.Distance(s.vector(c), exact.bound()), c);
      int32_t* out = s.nearest.data() + size_t(t) * s.list_length;
      out[0] = t;
      int at = 1;
      for (const auto& [dist, c] : exact.Sorted()) out[at++] = c;
      for (; at < s.list_length; ++at) out[at] = t;  // fewer similar texels than asked: repeat the texel
    }
  }, num_threads);
  return !CancelRequested();
}

StatusOr<std::vector<SampleLevel>> MakeSampleLevels(const TextonAnalysis& analysis, int levels, int n, int k, int num_threads) {
  std::vector<SampleLevel> samples(std::min<size_t>(size_t(std::max(levels, 0)), analysis.levels.size()));
  for (size_t l = 0; l < samples.size(); ++l) {
    samples[l] = MakeSampleLevel(analysis.levels[l], n);
    if (k > 0 && !BuildNearestLists(samples[l], k, num_threads)) return Status::Cancelled();
  }
  return samples;
}

bool SampleLevelsFit(const std::vector<SampleLevel>& samples, const TextonAnalysis& analysis, int levels, int n, int k) {
  if (int(samples.size()) < levels || levels > int(analysis.levels.size())) return false;
  for (int l = 0; l < levels; ++l) {
    const SampleLevel& s = samples[size_t(l)];
    if (s.level != &analysis.levels[size_t(l)] || s.slot_count() != n * n - 1) return false;
    if (k > 0 && s.list_length != std::max(1, std::min(k, s.texels()))) return false;
  }
  return true;
}

}  // namespace mesocap
