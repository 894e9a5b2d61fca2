#include "synth/texton_synthesis.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>

#include <Eigen/Eigenvalues>

#include "core/parallel.h"
#include "core/splitmix.h"
#include "synth/synth_quality.h"

namespace mesocap {
namespace {

constexpr float kInfinity = std::numeric_limits<float>::infinity();
constexpr int kEmbeddingDimensions = 8;  // texton coordinates per slot in the neighbourhood summary
constexpr int kSummaryDimensions = 12;   // principal components of the summary (L&H 2006 keep 8 of theirs)
constexpr int kRerankFactor = 4;         // summary-nearest texels re-ranked by the exact distance, per list entry
constexpr int kListBlock = 64;           // texels whose lists one task builds
constexpr int kPcaRows = 4096;           // texels the summaries' principal components are found from

struct Offset {
  int dx = 0, dy = 0;
};

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

int Wrap(int i, int n) {  // offsets are a few texels: no division
  while (i < 0) i += n;
  while (i >= n) i -= n;
  return i;
}

// One stack level of the sample with what the search needs: per texel the labels of its
// neighbourhood (spaced by the level's spacing; `outside` where a slot leaves the sample), and per
// texel the list of its most similar others. Every texel is a candidate.
struct SampleLevel {
  const TextonLevel* level = nullptr;
  int spacing = 1;
  // Per label, and for `outside`, a row of distances to every label, then to `outside`: a slot
  // beyond the sample costs half the typical distance between two of the sample's texels
  // (kOutsideCost), and nothing against another such slot.
  std::vector<float> distances;
  int stride = 0, outside = 0;
  std::vector<Offset> slots;     // the template
  std::vector<uint16_t> vectors;  // texels x slots
  int list_length = 0;
  std::vector<int32_t> nearest;  // texels x list_length: the texel itself, then similar others

  int width() const { return level->width; }
  int height() const { return level->height; }
  int texels() const { return level->width * level->height; }
  int slot_count() const { return int(slots.size()); }
  const uint16_t* vector(int t) const { return vectors.data() + size_t(t) * slots.size(); }
  const float* Row(int label) const { return distances.data() + size_t(label) * stride; }
  bool Inside(int x, int y) const { return x >= 0 && y >= 0 && x < width() && y < height(); }
};

// A texel near the border is a candidate like any other, its slots beyond the sample costed at
// kOutsideCost x the typical distance (the mean over pairs of the sample's texels). Candidates
// restricted to whole neighbourhoods left a rim of a quarter of the sample unused at coarse levels
// and the output's histograms drifted toward the sample's centre's: on the 20 photographs the
// subband statistics were 1.74x random tiling's (geometric mean), 1.32x with every texel; random
// tiling from the centre alone scores 1.8-2.5x. Half the typical distance (the distance to the
// mean, as Tong's default texton) measured best: 1 gave 1.47x, 0.25 more repeats (7.6%), 0 2.2x.
constexpr double kOutsideCost = 0.5;

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

// A neighbourhood to match: one distance-table row per slot.
struct Query {
  std::vector<const float*> rows;
  // Sum over slots; stops once it exceeds `bound` (a candidate that cannot win).
  float Distance(const uint16_t* candidate, float bound) const {
    float d = 0;
    const size_t n = rows.size();
    size_t i = 0;
    for (; i + 4 <= n; i += 4) {  // independent pairs: no chain of dependent adds
      d += (rows[i][candidate[i]] + rows[i + 1][candidate[i + 1]]) + (rows[i + 2][candidate[i + 2]] + rows[i + 3][candidate[i + 3]]);
      if (d > bound) return d;
    }
    for (; i < n; ++i) d += rows[i][candidate[i]];
    return d;
  }
};

Query SampleQuery(const SampleLevel& s, int t) {
  Query q;
  const uint16_t* v = s.vector(t);
  for (int j = 0; j < s.slot_count(); ++j) q.rows.push_back(s.Row(v[j]));
  return q;
}

// Keeps the `size` smallest (distance, texel) pairs seen.
class Nearest {
 public:
  explicit Nearest(int size) : size_(size) {}
  float bound() const { return int(heap_.size()) < size_ ? kInfinity : heap_.front().first; }
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

struct Counters {
  long queries = 0, candidates = 0, audited = 0, agreed = 0;
  Counters& operator+=(const Counters& o) {
    queries += o.queries, candidates += o.candidates, audited += o.audited, agreed += o.agreed;
    return *this;
  }
};

// A level's output: sample texel indices, wrapping.
struct Grid {
  std::vector<int32_t> texels;
  int width = 0, height = 0;
  int32_t At(int u, int v) const { return texels[size_t(Wrap(v, height)) * width + Wrap(u, width)]; }
};

// Corrects single texels of a level against a fixed state of the grid (a sub-pass's start).
class Corrector {
 public:
  Corrector(const SampleLevel& s, const TextonSynthesisOptions& o, Counters* counters)
      : s_(s), o_(o), counters_(counters), stamp_(size_t(s.texels()), 0), coherent_weight_(float(1 - o.coherence)) {
    query_.rows.resize(s.slots.size());
  }

  // The best sample texel for output texel (u, v) of `grid`; `draw` decides the audit.
  int32_t Texel(const Grid& grid, int u, int v, uint64_t draw) {
    for (int j = 0; j < s_.slot_count(); ++j)
      query_.rows[j] = s_.Row(s_.level->labels[grid.At(u + s_.slots[j].dx, v + s_.slots[j].dy)]);
    for (int j = 0, k = 0; j < 9; ++j)
      if (j != 4) around_[k++] = grid.At(u + j % 3 - 1, v + j / 3 - 1);
    int32_t best_texel = grid.At(u, v);
    const bool full = o_.search == TextonSearch::kFull;
    const float chosen = full ? FullSearch(&best_texel) : Coherent(grid, u, v, &best_texel);
    ++counters_->queries;
    if (o_.audit_fraction > 0 && double(SplitMix64(draw) >> 11) * 0x1p-53 < o_.audit_fraction) {
      ++counters_->audited;
      const float found = full ? chosen : candidates_.empty() ? kInfinity : CandidatesBest();
      counters_->agreed += found <= FullSearch(nullptr) * (1 + 1e-5f) + 1e-9f;
    }
    return best_texel;
  }

 private:
  // k-coherence: the continuations of the 3 x 3 nearest output texels and their similar texels.
  // A candidate that continues at least one of the 8 neighbours is coherent: it wins against one
  // up to 1 / (1 - coherence) times closer, and among equal distances (frequent: textons quantise
  // appearance) the candidate continuing more neighbours wins. Without that rule a texel copying
  // its neighbour's source ties with the neighbour's continuation wherever adjacent texels share
  // a texton, and one sample texel is stretched across the output.
  float Coherent(const Grid& grid, int u, int v, int32_t* best_texel) {
    ++query_id_;
    const int W = s_.width(), h = s_.spacing;
    int32_t continued[9];  // per 3 x 3 neighbour (the texel itself at 4), its source continued to (u, v)
    for (int j = 0; j < 9; ++j) {
      const int dx = j % 3 - 1, dy = j / 3 - 1;
      const int32_t t = grid.At(u + dx, v + dy);
      const int sx = t % W - h * dx, sy = t / W - h * dy;
      continued[j] = s_.Inside(sx, sy) ? sy * W + sx : -1;
    }
    auto support = [&](int32_t c) {
      int n = 0;
      for (int j = 0; j < 9; ++j) n += j != 4 && continued[j] == c;
      return n;
    };
    candidates_.clear();
    for (int j = 0; j < 9; ++j) {
      if (continued[j] < 0) continue;
      const int32_t* list = s_.nearest.data() + size_t(continued[j]) * s_.list_length;
      for (int i = 0; i < s_.list_length; ++i)
        if (stamp_[list[i]] != query_id_) stamp_[list[i]] = query_id_, candidates_.push_back(list[i]);
    }
    counters_->candidates += long(candidates_.size());
    if (candidates_.empty()) return query_.Distance(s_.vector(*best_texel), kInfinity);  // nothing continues: keep it
    float best = kInfinity;
    int best_support = -1;
    for (int32_t c : candidates_) {
      if (Beside(c)) continue;
      const int n = support(c);
      const float weight = n > 0 ? coherent_weight_ : 1.f;
      const float d = weight * query_.Distance(s_.vector(c), best / weight);
      if (d < best || (d == best && n > best_support)) best = d, best_support = n, *best_texel = c;
    }
    return best;
  }

  // True when sample texel c is the source of one of the texel's 8 neighbours: a sample texel is
  // never its own neighbour, so such a choice would stretch it across the output (a streak) and it
  // is never made (repeats on the 20 photographs fell from 2.1-4.8% of the texels to none).
  bool Beside(int32_t c) const {
    for (int32_t a : around_)
      if (a == c) return true;
    return false;
  }

  // The least distance among the last query's candidates, unweighted: what the audit compares
  // with the full search (the search's quality, apart from the coherence bias).
  float CandidatesBest() const {
    float best = kInfinity;
    for (int32_t c : candidates_)
      if (!Beside(c)) best = std::min(best, query_.Distance(s_.vector(c), best));
    return best;
  }

  // The best of every sample texel (lowest index on ties) into *best_texel if given.
  float FullSearch(int32_t* best_texel) const {
    float best = kInfinity;
    int32_t best_t = 0;
    for (int32_t t = 0; t < s_.texels(); ++t) {
      if (Beside(t)) continue;
      const float d = query_.Distance(s_.vector(t), best);
      if (d < best) best = d, best_t = t;
    }
    if (best_texel) *best_texel = best_t;
    return best;
  }

  const SampleLevel& s_;
  const TextonSynthesisOptions& o_;
  Counters* counters_;
  Query query_;
  int32_t around_[8] = {};  // the sources of the texel's 8 neighbours
  std::vector<int32_t> candidates_;
  std::vector<uint32_t> stamp_;
  uint32_t query_id_ = 0;
  float coherent_weight_;
};

// Random sample texels: the coarsest level's start.
Grid RandomGrid(const SampleLevel& s, int width, int height, uint64_t salt) {
  Grid g{std::vector<int32_t>(size_t(width) * height), width, height};
  for (size_t i = 0; i < g.texels.size(); ++i) g.texels[i] = int32_t(SplitMix64(salt + i) % uint64_t(s.texels()));
  return g;
}

// L&H §3.2: each texel of the level above spawns four whose coordinates continue it by the
// level's spacing, each then jittered (a uniform draw of up to jitter x spacing per axis) and kept
// inside the sample.
Grid Upsampled(const Grid& above, const SampleLevel& s, int width, int height, double jitter, uint64_t salt) {
  Grid g{std::vector<int32_t>(size_t(width) * height), width, height};
  const int W = s.width(), H = s.height(), h = s.spacing, reach = int(std::floor(jitter * h));
  for (int v = 0; v < height; ++v)
    for (int u = 0; u < width; ++u) {
      const int32_t p = above.texels[size_t(v / 2) * above.width + u / 2];
      // The parent's four children stay distinct: a parent within h of the far border spawns them
      // from h inside it.
      int x = std::clamp(p % W, 0, std::max(0, W - 1 - h)) + h * (u % 2);
      int y = std::clamp(p / W, 0, std::max(0, H - 1 - h)) + h * (v % 2);
      if (reach > 0) {
        const uint64_t r = SplitMix64(salt ^ (uint64_t(v) << 32 | uint32_t(u)));
        x += int(r % uint64_t(2 * reach + 1)) - reach;
        y += int((r >> 32) % uint64_t(2 * reach + 1)) - reach;
      }
      x = std::clamp(x, 0, W - 1), y = std::clamp(y, 0, H - 1);
      g.texels[size_t(v) * width + u] = y * W + x;
    }
  return g;
}

constexpr int kSubpassOrder[4][2] = {{0, 0}, {1, 1}, {1, 0}, {0, 1}};  // (x, y) parities, diagonal pairs first

// One correction pass (L&H §3.4): four sub-passes, each correcting one interleaved class of texels
// against the state the sub-pass began with (so rows run in parallel with the same result).
bool CorrectionPass(const SampleLevel& s, const TextonSynthesisOptions& o, uint64_t salt, Grid& grid, Counters* counters,
                    const ProgressFn& progress, long* done, long total, const std::string& what) {
  for (const auto& parity : kSubpassOrder) {
    const Grid before = grid;
    const int rows = (grid.height - parity[1] + 1) / 2;
    std::vector<Counters> row_counters(std::max(0, rows));
    ParallelFor(0, rows, [&](int r) {
      const int v = 2 * r + parity[1];
      Corrector corrector(s, o, &row_counters[r]);
      for (int u = parity[0]; u < grid.width; u += 2)
        grid.texels[size_t(v) * grid.width + u] =
            corrector.Texel(before, u, v, SplitMix64(salt ^ (uint64_t(v) << 32 | uint32_t(u))));
    }, o.num_threads);
    for (const Counters& c : row_counters) *counters += c;
    *done += rows;
    if (!ReportProgress(progress, int(std::min<long>(*done, total)), int(total), what)) return false;
  }
  return true;
}

}  // namespace

Status TextonSynthesisOptions::Check() const {
  if (width < 1 || height < 1 || width > 32768 || height > 32768) return Status::Error("the output size must be 1..32768 a side");
  if (k < 1 || k > 64) return Status::Error("k must be 1..64");
  if (neighbourhood < 3 || neighbourhood % 2 == 0 || neighbourhood > 15)
    return Status::Error("the neighbourhood must be odd, 3..15");
  if (levels < 0) return Status::Error("the levels must be at least 0 (0: all)");
  if (passes < 0 || passes > 16) return Status::Error("the passes must be 0..16");
  if (!(coherence >= 0 && coherence < 1)) return Status::Error("the coherence must be 0..1 (1 excluded)");
  if (!(jitter >= 0 && jitter <= 4)) return Status::Error("the jitter must be 0..4 (times the level's spacing)");
  if (!(audit_fraction >= 0 && audit_fraction <= 1)) return Status::Error("the audit fraction must be 0..1");
  return Status::Ok();
}

Status TextonSynthesisOptions::CheckSample(int sample_width, int sample_height) const {
  if (sample_width >= neighbourhood && sample_height >= neighbourhood) return Status::Ok();
  return Status::Error("the sample (" + std::to_string(sample_width) + "x" + std::to_string(sample_height) +
                       ") is smaller than the " + std::to_string(neighbourhood) + "x" + std::to_string(neighbourhood) +
                       " neighbourhood");
}

Status TextonSynthesisOptions::Check(const TextonAnalysis& analysis) const {
  MESOCAP_RETURN_IF_ERROR(Check());
  if (analysis.levels.empty()) return Status::Error("the texton analysis has no levels");
  return CheckSample(analysis.levels[0].width, analysis.levels[0].height);
}

StatusOr<SynthMap> TextonSynthesis(const TextonAnalysis& analysis, const TextonSynthesisOptions& o,
                                   TextonSynthesisReport* report, const ProgressFn& progress) {
  MESOCAP_RETURN_IF_ERROR(o.Check(analysis));
  const auto start = std::chrono::steady_clock::now();
  const int levels = o.levels > 0 ? std::min<int>(o.levels, int(analysis.levels.size())) : int(analysis.levels.size());
  // Output sizes per level, halving (rounded up): level l's texels stand 2^l output texels apart.
  std::vector<int> out_w(levels), out_h(levels);
  out_w[0] = o.width, out_h[0] = o.height;
  for (int l = 1; l < levels; ++l) out_w[l] = (out_w[l - 1] + 1) / 2, out_h[l] = (out_h[l - 1] + 1) / 2;

  std::vector<SampleLevel> samples(levels);
  for (int l = 0; l < levels; ++l) {
    samples[l] = MakeSampleLevel(analysis.levels[l], o.neighbourhood);
    if (o.search == TextonSearch::kCoherence && !BuildNearestLists(samples[l], o.k, o.num_threads))
      return Status::Cancelled();
  }
  const auto lists_done = std::chrono::steady_clock::now();

  long total_rows = 0;
  for (int l = 0; l < levels; ++l) total_rows += long(o.passes) * 2 * out_h[l];
  long rows_done = 0;
  std::vector<Counters> per_level(levels);
  const int top = levels - 1;
  auto salt = [&](int l, int pass) { return SplitMix64(SplitMix64(o.seed) ^ (uint64_t(l) << 8 | uint64_t(pass))); };
  Grid grid = RandomGrid(samples[top], out_w[top], out_h[top], salt(top, 0));
  for (int l = top; l >= 0; --l) {
    const SampleLevel& s = samples[l];
    if (l < top) grid = Upsampled(grid, s, out_w[l], out_h[l], o.jitter, salt(l, 0));
    // The counters keep the last pass, whose choices are the level's output.
    for (int pass = 1; pass <= o.passes; ++pass) {
      per_level[l] = Counters();
      if (!CorrectionPass(s, o, salt(l, pass), grid, &per_level[l], progress, &rows_done, total_rows,
                          "level " + std::to_string(l)))
        return Status::Cancelled();
    }
  }

  const SampleLevel& finest = samples[0];
  SynthMap map(o.width, o.height, finest.width(), finest.height(), "texton");
  for (int y = 0; y < o.height; ++y)
    for (int x = 0; x < o.width; ++x) {
      const int32_t t = grid.texels[size_t(y) * o.width + x];
      map.Set(x, y, float(t % finest.width()) + 0.5f, float(t / finest.width()) + 0.5f, 0.f, 0);
    }
  map.patch = CoherentRegions(map);  // seams are where the source jumps
  if (report) {
    const auto end = std::chrono::steady_clock::now();
    Counters counters;
    report->per_level.clear();
    for (const Counters& c : per_level) {
      counters += c;
      report->per_level.push_back({c.queries, c.queries ? double(c.candidates) / c.queries : 0, c.audited,
                                   c.audited ? double(c.agreed) / c.audited : 0});
    }
    report->levels = levels;
    report->queries = counters.queries;
    report->mean_candidates = counters.queries ? double(counters.candidates) / counters.queries : 0;
    report->audited = counters.audited;
    report->full_search_agreement = counters.audited ? double(counters.agreed) / counters.audited : 0;
    report->seconds_neighbours = std::chrono::duration<double>(lists_done - start).count();
    report->seconds_synthesis = std::chrono::duration<double>(end - lists_done).count();
    report->seconds = std::chrono::duration<double>(end - start).count();
  }
  return map;
}

}  // namespace mesocap
