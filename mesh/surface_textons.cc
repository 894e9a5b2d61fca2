#include "mesh/surface_textons.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "core/parallel.h"
#include "core/splitmix.h"
#include "mesh/mesh_pyramid.h"
#include "synth/texton_sample.h"

namespace mesocap {
namespace {

constexpr int kBlock = 256;  // vertices per parallel task
constexpr int kSurfaceLevelSteps = 8;  // see SurfaceTextonSynthesis

// One template slot of one vertex: the surface texton w0 t(v0) + w1 t(v1) + w2 t(v2); v[0] < 0
// for the default texton (no triangle covers the slot).
struct Slot {
  int32_t v[3] = {-1, -1, -1};
  float w[3] = {0, 0, 0};
};

struct Level {
  const TriangleMesh* mesh = nullptr;
  TangentFrames frames;
  VertexAdjacency ring;
  double spacing = 1;      // surface length between template slots (2^l texels)
  std::vector<Slot> slots; // vertices x template slots
  double uncovered = 0;
};

// Resamples every vertex's template in its (s, t) plane (Tong Fig. 4): the triangles around the
// vertex, reached breadth first while within the template's reach, projected onto the plane; each
// slot takes the first front-facing projected triangle containing it (nearest first).
void BuildTemplates(Level& L, const std::vector<Offset>& offsets, int num_threads) {
  const TriangleMesh& m = *L.mesh;
  const int V = m.vertex_count(), S = int(offsets.size());
  const VertexAdjacency faces = VertexFaces(m);
  int reach_slots = 0;
  for (const Offset& o : offsets) reach_slots = std::max({reach_slots, std::abs(o.dx), std::abs(o.dy)});
  const double reach = (reach_slots * std::sqrt(2.0) + 1.5) * L.spacing;
  L.slots.assign(size_t(V) * S, Slot());
  std::vector<long> uncovered((V + kBlock - 1) / kBlock, 0);
  ParallelFor(0, (V + kBlock - 1) / kBlock, [&](int b) {
    std::vector<uint32_t> seen_vertex(V, 0), seen_face(m.face_count(), 0);
    std::vector<int32_t> queue, face_order;
    for (int v = b * kBlock; v < std::min(V, (b + 1) * kBlock); ++v) {
      const uint32_t stamp = uint32_t(v + 1);
      const Eigen::Vector3d& p = m.positions[v];
      const Eigen::Vector3d &s = L.frames.s[v], &t = L.frames.t[v], &n = L.frames.n[v];
      queue.assign(1, v), face_order.clear();
      seen_vertex[v] = stamp;
      for (size_t head = 0; head < queue.size(); ++head) {
        const int32_t a = queue[head];
        for (const int32_t* f = faces.begin(a); f != faces.end(a); ++f)
          if (seen_face[*f] != stamp) seen_face[*f] = stamp, face_order.push_back(*f);
        for (const int32_t* u = L.ring.begin(a); u != L.ring.end(a); ++u)
          if (seen_vertex[*u] != stamp && (m.positions[*u] - p).norm() <= reach) seen_vertex[*u] = stamp, queue.push_back(*u);
      }
      Slot* out = L.slots.data() + size_t(v) * S;
      int filled = 0;
      for (int32_t f : face_order) {
        if (filled == S) break;
        if (m.FaceNormal(f).dot(n) <= 0) continue;  // seen from behind in this vertex's plane
        const auto& tri = m.faces[f];
        Eigen::Vector2d q[3];
        for (int k = 0; k < 3; ++k) {
          const Eigen::Vector3d d = (m.positions[tri[k]] - p) / L.spacing;
          q[k] = {d.dot(s), d.dot(t)};
        }
        const Eigen::Vector2d e0 = q[1] - q[0], e1 = q[2] - q[0];
        const double det = e0.x() * e1.y() - e1.x() * e0.y();
        if (det <= 1e-12) continue;
        for (int j = 0; j < S; ++j) {
          if (out[j].v[0] >= 0) continue;
          const Eigen::Vector2d r = Eigen::Vector2d(offsets[j].dx, -offsets[j].dy) - q[0];
          const double w1 = (r.x() * e1.y() - e1.x() * r.y()) / det, w2 = (e0.x() * r.y() - r.x() * e0.y()) / det;
          const double w0 = 1 - w1 - w2;
          if (w0 < -1e-9 || w1 < -1e-9 || w2 < -1e-9) continue;
          out[j].v[0] = tri[0], out[j].v[1] = tri[1], out[j].v[2] = tri[2];
          out[j].w[0] = float(std::max(0.0, w0)), out[j].w[1] = float(std::max(0.0, w1)), out[j].w[2] = float(std::max(0.0, w2));
          ++filled;
        }
      }
      uncovered[b] += S - filled;
    }
  }, num_threads);
  long total = 0;
  for (long u : uncovered) total += u;
  L.uncovered = V ? double(total) / (double(V) * S) : 0;
}

// A vertex's neighbourhood to match: per slot up to three (row, weight) terms of the distance
// table and a constant, so a candidate's distance is a constant plus weighted lookups.
class SurfaceQuery {
 public:
  void Build(const SampleLevel& s, const Slot* slots, int count, const std::vector<int32_t>& label, bool interpolate) {
    terms_.clear(), ends_.clear(), constant_ = 0;
    for (int j = 0; j < count; ++j) {
      const Slot& slot = slots[j];
      if (slot.v[0] < 0) {
        terms_.push_back({s.Row(s.level->default_texton()), 1.f});
      } else {
        int a[3];
        float w[3];
        int n = 0;
        int top = 0;
        for (int k = 1; k < 3; ++k)
          if (slot.w[k] > slot.w[top]) top = k;
        for (int k = 0; k < 3; ++k) {
          if (!interpolate && k != top) continue;  // the nearest vertex's texton, weight 1
          const int l = label[slot.v[k]];
          int i = 0;
          while (i < n && a[i] != l) ++i;
          if (i == n) a[n] = l, w[n] = 0, ++n;
          w[i] += interpolate ? slot.w[k] : 1.f;
        }
        for (int i = 0; i < n; ++i) {
          terms_.push_back({s.Row(a[i]), w[i]});
          for (int k = i + 1; k < n; ++k) constant_ -= w[i] * w[k] * s.Row(a[i])[a[k]];
        }
      }
      ends_.push_back(int(terms_.size()));
    }
  }

  // The distance to a sample texel's neighbourhood vector; stops once past `bound`.
  float Distance(const uint16_t* candidate, float bound) const {
    float d = constant_;
    int t = 0;
    for (size_t j = 0; j < ends_.size(); ++j) {
      const uint16_t c = candidate[j];
      for (; t < ends_[j]; ++t) d += terms_[t].weight * terms_[t].row[c];
      if ((j & 3) == 3 && d > bound) return d;
    }
    return d;
  }

 private:
  struct Term {
    const float* row;
    float weight;
  };
  std::vector<Term> terms_;
  std::vector<int> ends_;
  float constant_ = 0;
};

struct Counters {
  long queries = 0, candidates = 0;
};

// Corrects single vertices of a level against its state at a sub-pass's start.
class VertexCorrector {
 public:
  VertexCorrector(const Level& L, const SampleLevel& s, double texel_size,
                  const SurfaceTextonOptions& o)
      : L_(L), s_(s), h_(texel_size),
        coherent_weight_(float(1 - o.coherence)), stamp_(size_t(s.texels()), 0),
        interpolate_(o.slot_textons == SlotTextons::kInterpolated) {}

  int32_t Best(int v, const std::vector<int32_t>& texel, const std::vector<int32_t>& label, Counters* counters) {
    const int W = s_.width(), S = s_.slot_count();
    query_.Build(s_, L_.slots.data() + size_t(v) * S, S, label, interpolate_);
    const Eigen::Vector3d& p = L_.mesh->positions[v];
    const Eigen::Vector3d &sv = L_.frames.s[v], &tv = L_.frames.t[v];
    continued_.clear(), around_.clear();
    for (const int32_t* u = L_.ring.begin(v); u != L_.ring.end(v); ++u) {
      around_.push_back(texel[*u]);
      const Eigen::Vector3d d = (L_.mesh->positions[*u] - p) / h_;
      const int x = int(std::lround(texel[*u] % W - d.dot(sv))), y = int(std::lround(texel[*u] / W + d.dot(tv)));
      if (s_.Inside(x, y)) continued_.push_back(y * W + x);
    }
    ++query_id_;
    candidates_.clear();
    auto add_list = [&](int32_t t) {
      const int32_t* list = s_.nearest.data() + size_t(t) * s_.list_length;
      for (int i = 0; i < s_.list_length; ++i)
        if (stamp_[list[i]] != query_id_) stamp_[list[i]] = query_id_, candidates_.push_back(list[i]);
    };
    add_list(texel[v]);
    for (int32_t t : continued_) add_list(t);
    ++counters->queries;
    counters->candidates += long(candidates_.size());
    int32_t best_texel = texel[v];
    float best = kTextonInfinity;
    int best_support = -1;
    for (int32_t c : candidates_) {
      if (std::find(around_.begin(), around_.end(), c) != around_.end()) continue;  // a neighbour's own source
      const int n = int(std::count(continued_.begin(), continued_.end(), c));
      const float weight = n > 0 ? coherent_weight_ : 1.f;
      const float d = weight * query_.Distance(s_.vector(c), best / weight);
      if (d < best || (d == best && n > best_support)) best = d, best_support = n, best_texel = c;
    }
    return best_texel;
  }

 private:
  const Level& L_;
  const SampleLevel& s_;
  double h_;
  float coherent_weight_;
  SurfaceQuery query_;
  std::vector<int32_t> continued_, around_, candidates_;
  std::vector<uint32_t> stamp_;
  uint32_t query_id_ = 0;
  bool interpolate_;
};

// Greedy colouring of the vertex graph: the correction's sub-passes.
std::vector<std::vector<int32_t>> ColourClasses(const VertexAdjacency& ring, int V) {
  std::vector<int> colour(V, -1);
  std::vector<std::vector<int32_t>> classes;
  std::vector<char> used;
  for (int v = 0; v < V; ++v) {
    used.assign(classes.size() + 1, 0);
    for (const int32_t* u = ring.begin(v); u != ring.end(v); ++u)
      if (colour[*u] >= 0) used[colour[*u]] = 1;
    int c = 0;
    while (used[c]) ++c;
    if (c == int(classes.size())) classes.emplace_back();
    colour[v] = c;
    classes[c].push_back(v);
  }
  return classes;
}

std::vector<int32_t> LabelsOf(const std::vector<int32_t>& texel, const TextonLevel& level) {
  std::vector<int32_t> label(texel.size());
  for (size_t v = 0; v < texel.size(); ++v) label[v] = level.labels[texel[v]];
  return label;
}

}  // namespace

Status SurfaceTextonOptions::Check() const {
  if (k < 1 || k > 64) return Status::Error("k must be 1..64");
  if (neighbourhood < 3 || neighbourhood % 2 == 0 || neighbourhood > 15) return Status::Error("the neighbourhood must be odd, 3..15");
  if (levels < 0) return Status::Error("the levels must be at least 0 (0: all)");
  if (passes < 0 || passes > 16) return Status::Error("the passes must be 0..16");
  if (!(coherence >= 0 && coherence < 1)) return Status::Error("the coherence must be 0..1 (1 excluded)");
  if (!(jitter >= 0 && jitter <= 4)) return Status::Error("the jitter must be 0..4 (times the level's spacing)");
  if (!(texel_size >= 0) || !std::isfinite(texel_size)) return Status::Error("the texel size must be a length, 0 or more");
  return Status::Ok();
}

Eigen::Vector2i SurfaceMap::SourceTexel(int v) const {
  return {std::clamp(int(std::floor(source_x[v])), 0, sample_width - 1),
          std::clamp(int(std::floor(source_y[v])), 0, sample_height - 1)};
}

StatusOr<SurfaceMap> SurfaceTextonSynthesis(const TriangleMesh& mesh, const TangentFrames& frames,
                                            const TextonAnalysis& analysis, const SurfaceTextonOptions& o,
                                            SurfaceTextonReport* report, const ProgressFn& progress) {
  MESOCAP_RETURN_IF_ERROR(o.Check());
  if (analysis.levels.empty()) return Status::Error("the texton analysis has no levels");
  if (frames.size() != mesh.vertex_count()) return Status::Error("the tangent frames do not match the mesh");
  const auto start = std::chrono::steady_clock::now();
  const double h = o.texel_size > 0 ? o.texel_size : MeanEdgeLength(mesh);
  if (!(h > 0)) return Status::Error("the mesh has no edge length to scale texels by");
  // On meshes, levels while the sample spans 8 steps of their spacing, as before the plane's went
  // to 3: with the coarser ones a torus' texture turned up to 11.5 deg off its field in one eighth
  // (bound 10, mesh/surface_textons_test).
  const int usable = LevelsSpanning(analysis, kSurfaceLevelSteps);
  const int wanted = o.levels > 0 ? std::min(o.levels, usable) : usable;
  auto pyramid = BuildMeshPyramid(mesh, wanted);
  if (!pyramid.ok()) return pyramid.status();
  const int levels = int(pyramid->size());
  const auto pyramid_done = std::chrono::steady_clock::now();

  // Per level: the sample's side (labels, lists) and the mesh's (frames, templates).
  StatusOr<std::vector<SampleLevel>> made_here = std::vector<SampleLevel>();
  if (!o.sample_levels) made_here = MakeSampleLevels(analysis, levels, o.neighbourhood, o.k, o.num_threads);
  else if (!SampleLevelsFit(*o.sample_levels, analysis, levels, o.neighbourhood, o.k))
    return Status::Error("the shared sample levels were made from another analysis or with other options");
  if (!made_here.ok()) return made_here.status();
  const std::vector<SampleLevel>& samples = o.sample_levels ? *o.sample_levels : *made_here;
  const auto lists_done = std::chrono::steady_clock::now();
  const std::vector<Offset> offsets = samples[0].slots;
  std::vector<Level> L(levels);
  const PointGrid finest(mesh.positions);
  for (int l = 0; l < levels; ++l) {
    L[l].mesh = &(*pyramid)[l];
    if (l == 0) {
      L[l].frames = frames;
    } else {
      std::vector<Eigen::Vector3d> directions(L[l].mesh->vertex_count());
      for (int v = 0; v < L[l].mesh->vertex_count(); ++v) directions[v] = frames.s[finest.Nearest(L[l].mesh->positions[v])];
      L[l].frames = FramesFromDirections(*L[l].mesh, directions);
    }
    L[l].ring = VertexNeighbours(*L[l].mesh);
    L[l].spacing = h * samples[l].spacing;
    BuildTemplates(L[l], offsets, o.num_threads);
    if (CancelRequested()) return Status::Cancelled();
  }
  const auto templates_done = std::chrono::steady_clock::now();

  std::vector<std::vector<std::vector<int32_t>>> classes(levels);
  long total = 0, done = 0;
  for (int l = 0; l < levels; ++l) {
    classes[l] = ColourClasses(L[l].ring, L[l].mesh->vertex_count());
    total += long(o.passes) * long(classes[l].size());
  }
  auto salt = [&](int l, int pass) { return SplitMix64(SplitMix64(o.seed) ^ (uint64_t(l) << 8 | uint64_t(pass))); };
  std::vector<SurfaceTextonLevelReport> level_reports(levels);
  std::vector<int32_t> texel;
  for (int l = levels - 1; l >= 0; --l) {
    const SampleLevel& s = samples[l];
    const TriangleMesh& m = *L[l].mesh;
    const int V = m.vertex_count(), W = s.width(), H = s.height();
    std::vector<int32_t> next(V);
    if (l == levels - 1) {
      for (int v = 0; v < V; ++v) next[v] = int32_t(SplitMix64(salt(l, 0) + uint64_t(v)) % uint64_t(s.texels()));
    } else {  // each vertex continues its nearest coarser vertex, jittered
      const Level& up = L[l + 1];
      const PointGrid coarse(up.mesh->positions);
      const int reach = int(std::floor(o.jitter * s.spacing));
      for (int v = 0; v < V; ++v) {
        const int u = coarse.Nearest(m.positions[v]);
        const Eigen::Vector3d d = (m.positions[v] - up.mesh->positions[u]) / h;
        int x = int(std::lround(texel[u] % W + d.dot(up.frames.s[u]))), y = int(std::lround(texel[u] / W - d.dot(up.frames.t[u])));
        if (reach > 0) {
          const uint64_t r = SplitMix64(salt(l, 0) ^ uint64_t(v));
          x += int(r % uint64_t(2 * reach + 1)) - reach, y += int((r >> 32) % uint64_t(2 * reach + 1)) - reach;
        }
        next[v] = std::clamp(y, 0, H - 1) * W + std::clamp(x, 0, W - 1);
      }
    }
    texel = next;
    std::vector<int32_t> label = LabelsOf(texel, *s.level);
    Counters counters;
    for (int pass = 1; pass <= o.passes; ++pass) {
      counters = Counters();
      for (const auto& cls : classes[l]) {
        const int blocks = (int(cls.size()) + kBlock - 1) / kBlock;
        std::vector<Counters> block_counters(blocks);
        ParallelFor(0, blocks, [&](int b) {
          if (CancelRequested()) return;
          VertexCorrector corrector(L[l], s, h, o);
          for (int i = b * kBlock; i < std::min(int(cls.size()), (b + 1) * kBlock); ++i)
            next[cls[i]] = corrector.Best(cls[i], texel, label, &block_counters[b]);
        }, o.num_threads);
        for (const Counters& c : block_counters) counters.queries += c.queries, counters.candidates += c.candidates;
        for (int32_t v : cls) texel[v] = next[v], label[v] = s.level->labels[next[v]];
        if (!ReportProgress(progress, int(++done), int(total), "level " + std::to_string(l))) return Status::Cancelled();
      }
    }
    level_reports[l] = {V, L[l].uncovered, counters.queries ? double(counters.candidates) / counters.queries : 0};
  }

  SurfaceMap map;
  map.method = "texton";
  map.sample_width = samples[0].width(), map.sample_height = samples[0].height();
  map.texel_size = h;
  const int W = samples[0].width();
  for (int v = 0; v < mesh.vertex_count(); ++v) {
    map.source_x.push_back(float(texel[v] % W) + 0.5f);
    map.source_y.push_back(float(texel[v] / W) + 0.5f);
    map.label.push_back(analysis.levels[0].labels[texel[v]]);
  }
  if (report) {
    const auto end = std::chrono::steady_clock::now();
    auto seconds = [](auto a, auto b) { return std::chrono::duration<double>(b - a).count(); };
    report->levels = level_reports;
    report->texel_size = h;
    report->seconds_pyramid = seconds(start, pyramid_done);
    report->seconds_lists = seconds(pyramid_done, lists_done);
    report->seconds_templates = seconds(lists_done, templates_done);
    report->seconds_synthesis = seconds(templates_done, end);
    report->seconds = seconds(start, end);
  }
  return map;
}

}  // namespace mesocap

namespace mesocap {

SurfaceMapUsage MeasureSurfaceMap(const TriangleMesh& mesh, const TangentFrames& frames, const SurfaceMap& map) {
  SurfaceMapUsage f;
  const VertexAdjacency ring = VertexNeighbours(mesh);
  long edges = 0, same = 0, coherent = 0;
  std::vector<char> used(size_t(map.sample_width) * map.sample_height, 0);
  for (int v = 0; v < mesh.vertex_count(); ++v) {
    const Eigen::Vector2i a = map.SourceTexel(v);
    used[size_t(a.y()) * map.sample_width + a.x()] = 1;
    for (const int32_t* u = ring.begin(v); u != ring.end(v); ++u) {
      ++edges, same += a == map.SourceTexel(*u);
      const Eigen::Vector3d d = (mesh.positions[*u] - mesh.positions[v]) / map.texel_size;
      const Eigen::Vector2d expected(map.source_x[v] + d.dot(frames.s[v]), map.source_y[v] - d.dot(frames.t[v]));
      coherent += (Eigen::Vector2d(map.source_x[*u], map.source_y[*u]) - expected).norm() <= 1.0;
    }
  }
  if (edges) f.repeats = double(same) / edges, f.coherent = double(coherent) / edges;
  long count = 0;
  for (char c : used) count += c;
  f.texels_used = used.empty() ? 0 : double(count) / double(used.size());
  return f;
}

}  // namespace mesocap
