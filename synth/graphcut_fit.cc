#include "synth/graphcut_fit.h"

#include <algorithm>
#include <cmath>

#include <maxflow.h>

#include "synth/feature_distance.h"

namespace mesocap {

SynthCanvas::SynthCanvas(int width, int height, const Image& sample, std::string method)
    : map(width, height, sample.width(), sample.height(), std::move(method)),
      features(width, height, sample.channels()),
      synthesized(size_t(width) * height, 0),
      sample_features(&sample) {}

float SynthCanvas::MaskAt(int x, int y) const {
  if (!sample_mask || !map.filled(x, y)) return 0.f;
  const Eigen::Vector2i s = map.SourceTexel(x, y);
  return sample_mask->at(s.x(), s.y());
}

namespace {

// The value the old patch of output texel (x, y) would have at (x + dx, y + dy): its source
// stepped in the patch's own orientation (clamped into the sample).
const float* ContinuedOld(const SynthCanvas& c, int x, int y, int dx, int dy) {
  const size_t i = c.map.index(x, y);
  const Eigen::Vector2d step = RotatedStep(dx, dy, c.map.rotation_deg[i]);
  const Image& s = *c.sample_features;
  const int sx = std::clamp(int(std::floor(c.map.source_x[i] + step.x())), 0, s.width() - 1);
  const int sy = std::clamp(int(std::floor(c.map.source_y[i] + step.y())), 0, s.height() - 1);
  return s.pixel(sx, sy);
}

}  // namespace

std::vector<FitFreedom> DefaultFreedom(const SynthCanvas& canvas, const PlacedPatch& p) {
  std::vector<FitFreedom> freedom(size_t(p.width) * p.height, FitFreedom::kFree);
  const int W = canvas.map.width, H = canvas.map.height;
  for (int y = 0; y < p.height; ++y)
    for (int x = 0; x < p.width; ++x) {
      const int ox = p.x0 + x, oy = p.y0 + y;
      FitFreedom& f = freedom[size_t(y) * p.width + x];
      if (!canvas.synthesized[size_t(oy) * W + ox]) {
        f = FitFreedom::kForceNew;
        continue;
      }
      const bool edge = x == 0 || y == 0 || x == p.width - 1 || y == p.height - 1;
      if (!edge) continue;
      for (auto [dx, dy] : {std::pair{-1, 0}, {1, 0}, {0, -1}, {0, 1}}) {
        const int nx = x + dx, ny = y + dy, ax = ox + dx, ay = oy + dy;
        const bool outside_window = nx < 0 || ny < 0 || nx >= p.width || ny >= p.height;
        if (outside_window && ax >= 0 && ay >= 0 && ax < W && ay < H && canvas.synthesized[size_t(ay) * W + ax])
          f = FitFreedom::kForceOld;
      }
    }
  return freedom;
}

CutResult FitPatch(const SynthCanvas& c, const PlacedPatch& p, const std::vector<FitFreedom>& freedom,
                   const FitOptions& options) {
  const int n = p.width * p.height;
  const int F = c.features.channels();
  const int W = c.map.width;
  constexpr double kInfinite = 1e30;
  maxflow::Graph_DDD graph(n + 2 * n, 4 * n);
  graph.add_node(n);
  auto node = [&](int x, int y) { return y * p.width + x; };
  auto filled = [&](int x, int y) { return c.synthesized[size_t(p.y0 + y) * W + p.x0 + x] != 0; };
  auto old_at = [&](int x, int y) { return c.features.pixel(p.x0 + x, p.y0 + y); };

  // Terminals: SOURCE = old, SINK = new; add_tweights(i, cost of new, cost of old).
  for (int y = 0; y < p.height; ++y)
    for (int x = 0; x < p.width; ++x) {
      const FitFreedom f = freedom[node(x, y)];
      double cost_new = 0, cost_old = 0;
      if (f == FitFreedom::kForceNew) cost_old = kInfinite;
      if (f == FitFreedom::kForceOld) cost_new = kInfinite;
      if (options.data_weight > 0 && c.target && c.sample_mask) {
        const float m0 = c.target->at(p.x0 + x, p.y0 + y);
        const float m_new = p.copy->constraint.empty() ? 0.f : p.copy->constraint.at(p.u0 + x, p.v0 + y);
        cost_new += options.data_weight * std::abs(m_new - m0);
        if (filled(x, y)) cost_old += options.data_weight * std::abs(c.MaskAt(p.x0 + x, p.y0 + y) - m0);
      }
      graph.add_tweights(node(x, y), cost_new, cost_old);
    }

  // Smoothness: M(p, q, A, B) = |A(p) - B(p)| + |A(q) - B(q)| (Kwatra), plus step_weight times the
  // mean step across the cut, (|A(p) - B(q)| + |B(p) - A(q)|) / 2: where A and B agree (a periodic
  // material copied a period away) M is ~0 everywhere and the cut would land at an arbitrary
  // phase of the pattern; the second term puts it where the material itself is smooth.
  auto edge_cost = [&](const float* ap, const float* aq, const float* bp, const float* bq) {
    return FeatureDistance(ap, bp, F) + FeatureDistance(aq, bq, F) +
           0.5 * options.step_weight * (FeatureDistance(ap, bq, F) + FeatureDistance(bp, aq, F));
  };
  struct Edge {
    int a, b;
    double weight;        // cost when a and b differ (plain edge)
    int seam_node = -1;   // Kwatra's seam node, when a and b came from different old patches
    double to_a = 0, to_b = 0, old_seam = 0;
  };
  std::vector<Edge> edges;
  edges.reserve(2 * n);
  for (int y = 0; y < p.height; ++y)
    for (int x = 0; x < p.width; ++x)
      for (auto [dx, dy] : {std::pair{1, 0}, {0, 1}}) {
        const int x2 = x + dx, y2 = y + dy;
        if (x2 >= p.width || y2 >= p.height) continue;
        const bool fa = filled(x, y), fb = filled(x2, y2);
        if (!fa && !fb) continue;  // both must take the new patch: nothing to cut
        const float* new_a = p.NewFeatures(p.x0 + x, p.y0 + y);
        const float* new_b = p.NewFeatures(p.x0 + x2, p.y0 + y2);
        Edge e{node(x, y), node(x2, y2), 0};
        const int32_t patch_a = fa ? c.map.patch[c.map.index(p.x0 + x, p.y0 + y)] : -1;
        const int32_t patch_b = fb ? c.map.patch[c.map.index(p.x0 + x2, p.y0 + y2)] : -1;
        if (fa && fb && patch_a != patch_b) {
          // Old seam between a and b: A_a continued to b and A_b continued back to a.
          const float* a_at_b = ContinuedOld(c, p.x0 + x, p.y0 + y, dx, dy);
          const float* b_at_a = ContinuedOld(c, p.x0 + x2, p.y0 + y2, -dx, -dy);
          e.to_a = edge_cost(old_at(x, y), a_at_b, new_a, new_b);
          e.to_b = edge_cost(b_at_a, old_at(x2, y2), new_a, new_b);
          e.old_seam = edge_cost(old_at(x, y), a_at_b, b_at_a, old_at(x2, y2));
          e.seam_node = graph.add_node();
          graph.add_edge(e.a, e.seam_node, e.to_a, e.to_a);
          graph.add_edge(e.seam_node, e.b, e.to_b, e.to_b);
          graph.add_tweights(e.seam_node, 0, e.old_seam);
        } else {
          const float* old_a = fa ? old_at(x, y) : ContinuedOld(c, p.x0 + x2, p.y0 + y2, -dx, -dy);
          const float* old_b = fb ? old_at(x2, y2) : ContinuedOld(c, p.x0 + x, p.y0 + y, dx, dy);
          e.weight = edge_cost(old_a, old_b, new_a, new_b);
          graph.add_edge(e.a, e.b, e.weight, e.weight);
        }
        edges.push_back(e);
      }
  graph.maxflow();

  CutResult cut;
  cut.take_new.resize(n);
  for (int i = 0; i < n; ++i) {
    cut.take_new[i] = graph.what_segment(i) == maxflow::Graph_DDD::SINK;
    cut.new_texels += cut.take_new[i];
  }
  for (const Edge& e : edges) {
    if (cut.take_new[e.a] == cut.take_new[e.b]) continue;
    cut.seam_cost += e.seam_node < 0 ? e.weight : (cut.take_new[e.a] ? e.to_b : e.to_a);
    ++cut.seam_edges;
  }
  return cut;
}

void CommitPatch(SynthCanvas* c, const PlacedPatch& p, const CutResult& cut) {
  const int id = c->next_patch++;
  const int F = c->features.channels();
  for (int y = 0; y < p.height; ++y)
    for (int x = 0; x < p.width; ++x) {
      if (!cut.take_new[size_t(y) * p.width + x]) continue;
      const int ox = p.x0 + x, oy = p.y0 + y, u = p.u0 + x, v = p.v0 + y;
      // The centre of the texel the copy was sampled at, so the map's lookup takes the same one.
      const Eigen::Vector2i s = p.copy->SourceTexel(u, v);
      c->map.Set(ox, oy, s.x() + 0.5f, s.y() + 0.5f, float(p.copy->rotation_deg), id);
      std::copy_n(p.copy->features.pixel(u, v), F, c->features.pixel(ox, oy));
      c->synthesized[size_t(oy) * c->map.width + ox] = 1;
    }
}

double MeanNeighbourStep(const Image& f) {
  double sum = 0;
  size_t count = 0;
  for (int y = 0; y < f.height(); ++y)
    for (int x = 0; x < f.width(); ++x) {
      if (x + 1 < f.width()) sum += FeatureDistance(f.pixel(x, y), f.pixel(x + 1, y), f.channels()), ++count;
      if (y + 1 < f.height()) sum += FeatureDistance(f.pixel(x, y), f.pixel(x, y + 1), f.channels()), ++count;
    }
  return count ? sum / count : 0.0;
}

}  // namespace mesocap
