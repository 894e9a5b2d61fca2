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
#include "synth/texton_sample.h"

namespace mesocap {
namespace {

constexpr float kInfinity = kTextonInfinity;

int Wrap(int i, int n) {  // offsets are a few texels: no division
  while (i < 0) i += n;
  while (i >= n) i -= n;
  return i;
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
  // Each level's children are grouped under their parents from a random offset (0 or 1 per axis),
  // so that no output line separates different parents at every level: with the groups aligned, the
  // lines at multiples of the coarsest spacing (the wrap-around edges among them) carried seams
  // 1.2-1.5x the rest's on brick, crackle and bark.
  const uint64_t shift = SplitMix64(salt ^ 0x5eedULL);
  const int ox = int(shift & 1), oy = int((shift >> 1) & 1);
  for (int v = 0; v < height; ++v)
    for (int u = 0; u < width; ++u) {
      const int pu = Wrap((u + ox) / 2, above.width), pv = Wrap((v + oy) / 2, above.height);
      const int32_t p = above.texels[size_t(pv) * above.width + pu];
      // The parent's four children stay distinct: a parent within h of the far border spawns them
      // from h inside it.
      int x = std::clamp(p % W, 0, std::max(0, W - 1 - h)) + h * ((u + ox) % 2);
      int y = std::clamp(p / W, 0, std::max(0, H - 1 - h)) + h * ((v + oy) % 2);
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

  auto made = MakeSampleLevels(analysis, levels, o.neighbourhood, o.search == TextonSearch::kCoherence ? o.k : 0, o.num_threads);
  if (!made.ok()) return made.status();
  const std::vector<SampleLevel>& samples = *made;
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
