#include "synth/texton_sample.h"

#include <algorithm>
#include <cmath>
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
  int d = 0;
  const std::vector<float> y = NeighbourhoodSummaries(s, &d);
  const int W = s.width(), blocks = (count + kListBlock - 1) / kListBlock, exclusion = std::max(2, s.spacing);
  ParallelFor(0, blocks, [&](int b) {
    if (CancelRequested()) return;
    std::vector<float> distance(count);
    Nearest summary(kRerankFactor * (s.list_length - 1)), exact(s.list_length - 1);
    for (int i = b * kListBlock; i < std::min(count, (b + 1) * kListBlock); ++i) {
      std::fill(distance.begin(), distance.end(), 0.f);
      for (int c = 0; c < d; ++c) {  // each candidate's sum in the same order, vectorised across candidates
        const float* component = y.data() + size_t(c) * count;
        const float own = component[i];
        for (int j = 0; j < count; ++j) distance[j] += (component[j] - own) * (component[j] - own);
      }
      const int32_t t = i;
      const int tx = t % W, ty = t / W;
      summary.Clear(), exact.Clear();
      for (int32_t c = 0; c < count; ++c) {
        if (distance[c] >= summary.bound()) continue;
        if (std::abs(c % W - tx) < exclusion && std::abs(c / W - ty) < exclusion) continue;
        summary.Offer(distance[c], c);
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
