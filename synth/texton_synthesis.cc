#include "synth/texton_synthesis.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <limits>
#include <numeric>
#include <optional>
#include <string>

#include "core/parallel.h"
#include "core/splitmix.h"

namespace mesocap {
namespace {

constexpr int kExhaustiveTexels = 64 * 64;  // the paper's limit for exhaustive k-nearest lists
constexpr int kParentCandidates = 100;      // m: nearest texels of the parent whose children are tried
constexpr float kInfinity = std::numeric_limits<float>::infinity();

struct Offset {
  int dx = 0, dy = 0;
};

// The n x n template around a texel, without the texel itself, nearest offsets first: a distance
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

bool Causal(const Offset& o) { return o.dy < 0 || (o.dy == 0 && o.dx < 0); }

int Wrap(int i, int n) {  // offsets are a few texels: no division
  while (i < 0) i += n;
  while (i >= n) i -= n;
  return i;
}

// One pyramid level of the sample with what the search needs: per texel the labels of its
// neighbourhood (own template, then the parent's), and the list of its nearest texels.
struct SampleLevel {
  const TextonLevel* level = nullptr;
  const TextonLevel* parent = nullptr;  // the level above; null at the coarsest
  std::vector<float> distances, parent_distances;
  std::vector<Offset> own, up;  // templates
  int slots = 0;
  std::vector<uint16_t> vectors;   // texels x slots
  // Texels whose whole neighbourhood (and their parent's) lies inside the sample: the only
  // candidates. A default texton in a candidate's neighbourhood sits near every texton (it is
  // their mean), so border texels would win matches they do not deserve; the full search then
  // collapses onto them. (All texels when no neighbourhood fits, on a tiny sample.)
  std::vector<uint8_t> valid;
  std::vector<int32_t> candidates;
  int list_length = 0;
  std::vector<int32_t> nearest;    // texels x list_length: the texel itself, then the nearest others

  int width() const { return level->width; }
  int height() const { return level->height; }
  int texels() const { return level->width * level->height; }
  const uint16_t* vector(int t) const { return vectors.data() + size_t(t) * slots; }
  const float* Row(int slot, int label) const {
    return slot < int(own.size()) ? distances.data() + size_t(label) * (level->textons + 1)
                                  : parent_distances.data() + size_t(label) * (parent->textons + 1);
  }
};

SampleLevel MakeSampleLevel(const TextonLevel& level, const TextonLevel* parent, int n, int p) {
  SampleLevel s;
  s.level = &level;
  s.parent = parent;
  s.distances = TextonDistances(level);
  s.own = Square(n);
  if (parent) {
    s.parent_distances = TextonDistances(*parent);
    s.up = Square(p);
    s.up.insert(s.up.begin(), Offset{0, 0});  // the parent itself first
  }
  s.slots = int(s.own.size() + s.up.size());
  s.vectors.resize(size_t(s.texels()) * s.slots);
  for (int y = 0; y < level.height; ++y)
    for (int x = 0; x < level.width; ++x) {
      uint16_t* v = s.vectors.data() + (size_t(y) * level.width + x) * s.slots;
      for (const Offset& o : s.own) {
        const int xx = x + o.dx, yy = y + o.dy;
        const bool inside = xx >= 0 && yy >= 0 && xx < level.width && yy < level.height;
        *v++ = uint16_t(inside ? level.label(xx, yy) : level.default_texton());
      }
      for (const Offset& o : s.up) {
        const int xx = x / 2 + o.dx, yy = y / 2 + o.dy;
        const bool inside = xx >= 0 && yy >= 0 && xx < parent->width && yy < parent->height;
        *v++ = uint16_t(inside ? parent->label(xx, yy) : parent->default_texton());
      }
    }
  s.valid.assign(size_t(s.texels()), 0);
  for (int t = 0; t < s.texels(); ++t) {
    const uint16_t* v = s.vector(t);
    bool complete = true;
    for (size_t j = 0; j < s.own.size(); ++j) complete &= v[j] != level.default_texton();
    for (size_t j = s.own.size(); j < size_t(s.slots); ++j) complete &= v[j] != parent->default_texton();
    if (complete) s.valid[t] = 1, s.candidates.push_back(t);
  }
  if (s.candidates.empty()) {
    s.valid.assign(size_t(s.texels()), 1);
    s.candidates.resize(size_t(s.texels()));
    std::iota(s.candidates.begin(), s.candidates.end(), 0);
  }
  return s;
}

// A neighbourhood to match: one distance-table row per slot in use (the query's label at that
// slot), and which slot of a candidate's vector each row is read with.
struct Query {
  std::vector<const float*> rows;
  std::vector<int> slots;
  bool all_slots = true;  // slots are 0, 1, 2, ...: read candidates without the indirection
  void Clear() { rows.clear(), slots.clear(), all_slots = true; }
  void Add(const SampleLevel& s, int slot, int label) {
    all_slots &= slot == int(slots.size());
    rows.push_back(s.Row(slot, label)), slots.push_back(slot);
  }
  // Sum over slots; stops once it exceeds `bound` (a candidate that cannot win).
  float Distance(const uint16_t* candidate, float bound) const {
    float d = 0;
    const size_t n = rows.size();
    if (all_slots) {  // four independent sums per block of eight slots: no chain of dependent adds
      size_t i = 0;
      for (; i + 8 <= n; i += 8) {
        const float a = rows[i][candidate[i]] + rows[i + 4][candidate[i + 4]];
        const float b = rows[i + 1][candidate[i + 1]] + rows[i + 5][candidate[i + 5]];
        const float c = rows[i + 2][candidate[i + 2]] + rows[i + 6][candidate[i + 6]];
        const float e = rows[i + 3][candidate[i + 3]] + rows[i + 7][candidate[i + 7]];
        d += (a + b) + (c + e);
        if (d > bound) return d;
      }
      for (; i < n; ++i) d += rows[i][candidate[i]];
      return d;
    }
    for (size_t i = 0; i < n; ++i) {
      d += rows[i][candidate[slots[i]]];
      if (d > bound) break;
    }
    return d;
  }
};

// The query of sample texel t against other sample texels (k-nearest lists).
Query SampleQuery(const SampleLevel& s, int t) {
  Query q;
  const uint16_t* v = s.vector(t);
  for (int j = 0; j < s.slots; ++j) q.Add(s, j, v[j]);
  return q;
}

// Keeps the `size` smallest (distance, texel) pairs seen.
class Nearest {
 public:
  explicit Nearest(int size) : size_(size) {}
  float bound() const { return heap_.empty() || int(heap_.size()) < size_ ? kInfinity : heap_.front().first; }
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

 private:
  int size_;
  std::vector<std::pair<float, int32_t>> heap_;
};

// Nearest lists of every texel of `s`: exhaustive on small levels, otherwise among the children
// of the parent's nearest texels (Tong §5.2).
void BuildNearestLists(SampleLevel& s, const SampleLevel* coarser, int length, int num_threads) {
  const int texels = s.texels();
  s.list_length = std::min(length, texels);
  s.nearest.assign(size_t(texels) * s.list_length, 0);
  const bool exhaustive = texels <= kExhaustiveTexels || !coarser;
  ParallelFor(0, s.height(), [&](int y) {
    std::vector<int32_t> candidates;
    for (int x = 0; x < s.width(); ++x) {
      const int t = y * s.width() + x;
      int32_t* out = s.nearest.data() + size_t(t) * s.list_length;
      out[0] = t;
      if (s.list_length == 1) continue;
      const Query q = SampleQuery(s, t);
      Nearest best(s.list_length - 1);
      candidates.clear();
      if (exhaustive) {
        candidates = s.candidates;
      } else {
        const int px = std::min(x / 2, coarser->width() - 1), py = std::min(y / 2, coarser->height() - 1);
        const int32_t* list = coarser->nearest.data() + size_t(py * coarser->width() + px) * coarser->list_length;
        for (int i = 0; i < coarser->list_length; ++i)
          for (int c = 0; c < 4; ++c) {
            const int cx = 2 * (list[i] % coarser->width()) + c % 2, cy = 2 * (list[i] / coarser->width()) + c / 2;
            if (cx < s.width() && cy < s.height() && s.valid[cy * s.width() + cx]) candidates.push_back(cy * s.width() + cx);
          }
      }
      for (int32_t c : candidates)
        if (c != t) {
          const float d = q.Distance(s.vector(c), best.bound());
          best.Offer(d, c);
        }
      int i = 1;
      for (const auto& [d, c] : best.Sorted()) out[i++] = c;
    }
  }, num_threads);
}

struct Counters {
  long queries = 0, candidates = 0, audited = 0, agreed = 0;
  Counters& operator+=(const Counters& o) {
    queries += o.queries, candidates += o.candidates, audited += o.audited, agreed += o.agreed;
    return *this;
  }
};

// The output of one level being synthesized: sample texel indices, out_w x out_h, wrapping. In a
// banded pass, rows outside the band being worked on are read from the pass's starting state.
struct OutputGrid {
  std::vector<int32_t>* texels = nullptr;
  const std::vector<int32_t>* before = nullptr;  // the pass's starting state (banded passes)
  int width = 0, height = 0, band_begin = 0, band_end = 0;
  int32_t At(int u, int v) const {
    u = Wrap(u, width), v = Wrap(v, height);
    const bool own = !before || (v >= band_begin && v < band_end);
    return (own ? *texels : *before)[size_t(v) * width + u];
  }
};

// One scanline sweep over some rows of a level's output: builds each texel's query, forms its
// candidates and keeps the best.
class Sweep {
 public:
  Sweep(const SampleLevel& s, const TextonSynthesisOptions& o, bool causal, uint64_t salt, Counters* counters)
      : s_(s), o_(o), causal_(causal), salt_(salt), counters_(counters), stamp_(size_t(s.texels()), 0) {
    for (int j = 0; j < int(s_.own.size()); ++j)
      if (!causal || Causal(s_.own[j])) own_slots_.push_back(j);
  }

  // Resynthesizes texel (u, v) of `grid`; `parent` (null at the coarsest level) is the level
  // above's output.
  void Texel(const OutputGrid& grid, const OutputGrid* parent, int u, int v) {
    query_.Clear();
    for (int j : own_slots_) query_.Add(s_, j, s_.level->labels[grid.At(u + s_.own[j].dx, v + s_.own[j].dy)]);
    if (!causal_ && parent)
      for (size_t j = 0; j < s_.up.size(); ++j)
        query_.Add(s_, int(s_.own.size() + j), s_.parent->labels[parent->At(u / 2 + s_.up[j].dx, v / 2 + s_.up[j].dy)]);
    int32_t& here = (*grid.texels)[size_t(v) * grid.width + u];
    const uint64_t draw = SplitMix64(salt_ ^ (uint64_t(v) << 32 | uint32_t(u)));
    const float chosen = Choose(grid, u, v, draw, &here);
    ++counters_->queries;
    if (o_.audit_fraction > 0 && double(SplitMix64(draw) >> 11) * 0x1p-53 < o_.audit_fraction) {
      ++counters_->audited;
      counters_->agreed += chosen <= FullSearch(nullptr) * (1 + 1e-5f) + 1e-9f;
    }
  }

 private:
  // Picks the best candidate for the current query into *here; returns its distance.
  float Choose(const OutputGrid& grid, int u, int v, uint64_t draw, int32_t* here) {
    if (o_.search == TextonSearch::kFull) {
      counters_->candidates += long(s_.candidates.size());
      return FullSearch(here);
    }
    ++query_id_;
    candidates_.clear();
    auto add_coherent = [&](int dx, int dy) {
      const int32_t t = grid.At(u + dx, v + dy);
      const int sx = t % s_.width() - dx, sy = t / s_.width() - dy;  // forward-shifted to (u, v)
      if (sx < 0 || sy < 0 || sx >= s_.width() || sy >= s_.height() || !s_.valid[sy * s_.width() + sx]) return;
      const int32_t* list = s_.nearest.data() + size_t(sy * s_.width() + sx) * s_.list_length;
      for (int i = 0; i < std::min(o_.k, s_.list_length); ++i)
        if (stamp_[list[i]] != query_id_) stamp_[list[i]] = query_id_, candidates_.push_back(list[i]);
    };
    // The texel's own source first: usually close, so the others' sums stop early against it.
    if (!causal_) add_coherent(0, 0);
    for (int j : own_slots_) add_coherent(s_.own[j].dx, s_.own[j].dy);
    counters_->candidates += long(candidates_.size());
    if (candidates_.empty()) {  // every neighbour's continuation leaves the sample
      if (causal_) *here = s_.candidates[draw % s_.candidates.size()];
      return query_.Distance(s_.vector(*here), kInfinity);
    }
    float best = kInfinity;
    for (int32_t c : candidates_) {
      const float d = query_.Distance(s_.vector(c), best);
      if (d < best) best = d, *here = c;
    }
    return best;
  }

  // The best of every sample texel (lowest index on ties) into *here if given; its distance.
  float FullSearch(int32_t* here) const {
    float best = kInfinity;
    int32_t best_t = 0;
    for (int32_t t : s_.candidates) {
      const float d = query_.Distance(s_.vector(t), best);
      if (d < best) best = d, best_t = t;
    }
    if (here) *here = best_t;
    return best;
  }

  const SampleLevel& s_;
  const TextonSynthesisOptions& o_;
  bool causal_;
  uint64_t salt_;
  Counters* counters_;
  std::vector<int> own_slots_;
  Query query_;
  std::vector<int32_t> candidates_;
  std::vector<uint32_t> stamp_;
  uint32_t query_id_ = 0;
};

constexpr int kBandRows = 32;  // rows a worker sweeps in a resynthesis pass (fixed: same result for any thread count)

// The coarsest level's causal pass, in one scanline sweep: each texel sees the ones before it.
bool CausalPass(const SampleLevel& s, const TextonSynthesisOptions& o, uint64_t salt, std::vector<int32_t>& out, int w,
                int h, Counters* counters, const ProgressFn& progress, const std::string& what) {
  Sweep sweep(s, o, true, salt, counters);
  const OutputGrid grid{&out, nullptr, w, h, 0, h};
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) sweep.Texel(grid, nullptr, u, v);
    if (!ReportProgress(progress, v + 1, h, what)) return false;
  }
  return true;
}

// A resynthesis pass with full neighbourhoods, in bands of rows swept in parallel; a band reads
// the rows of other bands as they were when the pass began.
bool ResynthesisPass(const SampleLevel& s, const TextonSynthesisOptions& o, uint64_t salt, std::vector<int32_t>& out, int w,
                     int h, const OutputGrid* parent, Counters* counters, const ProgressFn& progress, const std::string& what) {
  const std::vector<int32_t> before = out;
  const int bands = (h + kBandRows - 1) / kBandRows;
  std::vector<Counters> band_counters(bands);
  std::atomic<int> rows_done{0};
  std::atomic<bool> cancelled{false};
  ParallelFor(0, bands, [&](int b) {
    if (cancelled) return;
    const OutputGrid grid{&out, &before, w, h, b * kBandRows, std::min(h, (b + 1) * kBandRows)};
    Sweep sweep(s, o, false, salt, &band_counters[b]);
    for (int v = grid.band_begin; v < grid.band_end; ++v) {
      for (int u = 0; u < w; ++u) sweep.Texel(grid, parent, u, v);
      if (!ReportProgress(progress, ++rows_done, h, what)) cancelled = true;
    }
  }, o.num_threads);
  for (const Counters& c : band_counters) *counters += c;
  return !cancelled;
}

// Patch ids: texels joined to their right and lower neighbours when those continue the same
// source (coherent runs), so seams are where the source jumps.
std::vector<int32_t> CoherentPatches(const std::vector<int32_t>& out, int w, int h, int sample_w) {
  std::vector<int32_t> root(out.size());
  std::iota(root.begin(), root.end(), 0);
  auto find = [&](int32_t i) {
    while (root[i] != i) i = root[i] = root[root[i]];
    return i;
  };
  auto join = [&](int32_t a, int32_t b) { root[find(a)] = find(b); };
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int32_t i = y * w + x, t = out[i];
      if (x + 1 < w && out[i + 1] == t + 1 && (t + 1) % sample_w != 0) join(i + 1, i);
      if (y + 1 < h && out[i + w] == t + sample_w) join(i + w, i);
    }
  std::vector<int32_t> id(out.size(), -1), patch(out.size());
  int32_t next = 0;
  for (size_t i = 0; i < out.size(); ++i) {
    const int32_t r = find(int32_t(i));
    if (id[r] < 0) id[r] = next++;
    patch[i] = id[r];
  }
  return patch;
}

}  // namespace

Status TextonSynthesisOptions::Check() const {
  if (width < 1 || height < 1 || width > 32768 || height > 32768) return Status::Error("the output size must be 1..32768 a side");
  if (k < 1 || k > 64) return Status::Error("k must be 1..64");
  if (neighbourhood < 3 || neighbourhood % 2 == 0 || neighbourhood > 15)
    return Status::Error("the neighbourhood must be odd, 3..15");
  if (parent_neighbourhood < 1 || parent_neighbourhood % 2 == 0 || parent_neighbourhood > 15)
    return Status::Error("the parent neighbourhood must be odd, 1..15");
  if (levels < 0) return Status::Error("the levels must be at least 0 (0: all)");
  if (passes < 0 || passes > 16) return Status::Error("the passes must be 0..16");
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
  // Output sizes per level, halving (rounded up) like the sample's pyramid.
  std::vector<int> out_w(levels), out_h(levels);
  out_w[0] = o.width, out_h[0] = o.height;
  for (int l = 1; l < levels; ++l) out_w[l] = (out_w[l - 1] + 1) / 2, out_h[l] = (out_h[l - 1] + 1) / 2;

  std::vector<SampleLevel> samples(levels);
  for (int l = levels - 1; l >= 0; --l) {
    const TextonLevel* parent = l + 1 < levels ? &analysis.levels[l + 1] : nullptr;
    samples[l] = MakeSampleLevel(analysis.levels[l], parent, o.neighbourhood, o.parent_neighbourhood);
    if (o.search == TextonSearch::kCoherence)
      BuildNearestLists(samples[l], l + 1 < levels ? &samples[l + 1] : nullptr, l == 0 ? o.k : std::max(o.k, kParentCandidates),
                        o.num_threads);
  }
  const auto lists_done = std::chrono::steady_clock::now();

  std::vector<Counters> per_level(levels);
  std::vector<std::vector<int32_t>> out(levels);
  const int top = levels - 1;
  out[top].resize(size_t(out_w[top]) * out_h[top]);
  const std::vector<int32_t>& starts = samples[top].candidates;
  for (size_t i = 0; i < out[top].size(); ++i) out[top][i] = starts[SplitMix64(SplitMix64(o.seed) + i) % starts.size()];
  for (int l = top; l >= 0; --l) {
    const SampleLevel& s = samples[l];
    const std::string what = "level " + std::to_string(l);
    auto salt = [&](int pass) { return SplitMix64(SplitMix64(o.seed) ^ (uint64_t(l) << 8 | uint64_t(pass))); };
    if (l == top) {
      if (!CausalPass(s, o, salt(0), out[l], out_w[l], out_h[l], &per_level[l], progress, what))
        return Status::Error("cancelled");
    } else {  // every texel continues its parent's source
      out[l].resize(size_t(out_w[l]) * out_h[l]);
      const SampleLevel& up = samples[l + 1];
      for (int v = 0; v < out_h[l]; ++v)
        for (int u = 0; u < out_w[l]; ++u) {
          const int32_t p = out[l + 1][size_t(v / 2) * out_w[l + 1] + u / 2];
          const int sx = std::min(2 * (p % up.width()) + u % 2, s.width() - 1);
          const int sy = std::min(2 * (p / up.width()) + v % 2, s.height() - 1);
          out[l][size_t(v) * out_w[l] + u] = sy * s.width() + sx;
        }
    }
    // Resynthesis with full neighbourhoods; the counters keep the last pass, whose choices are the
    // level's output.
    std::optional<OutputGrid> parent;
    if (l < top) parent = OutputGrid{&out[l + 1], nullptr, out_w[l + 1], out_h[l + 1], 0, out_h[l + 1]};
    for (int pass = 1; pass <= o.passes; ++pass) {
      per_level[l] = Counters();
      if (!ResynthesisPass(s, o, salt(pass), out[l], out_w[l], out_h[l], parent ? &*parent : nullptr, &per_level[l], progress,
                           what))
        return Status::Error("cancelled");
    }
  }

  const SampleLevel& finest = samples[0];
  SynthMap map(o.width, o.height, finest.width(), finest.height(), "texton");
  const std::vector<int32_t> patch = CoherentPatches(out[0], o.width, o.height, finest.width());
  for (int y = 0; y < o.height; ++y)
    for (int x = 0; x < o.width; ++x) {
      const int32_t t = out[0][size_t(y) * o.width + x];
      map.Set(x, y, float(t % finest.width()) + 0.5f, float(t / finest.width()) + 0.5f, 0.f, patch[size_t(y) * o.width + x]);
    }
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
