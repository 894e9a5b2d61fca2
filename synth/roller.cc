#include "synth/roller.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <random>

#include <opencv2/core.hpp>

#include "core/median.h"
#include "core/parallel.h"
#include "core/text_format.h"
#include "synth/feature_distance.h"
#include "synth/graphcut_fit.h"
#include "synth/patch_matching.h"

namespace mesocap {

Status RollerOptions::Check() const {
  if (width < 1 || height < 1 || width > 32768 || height > 32768)
    return Status::Error(Format("output size %dx%d: each side must be 1..32768 texels", width, height));
  if (tiles < 1 || tiles > 64) return Status::Error("the number of tiles must be 1..64");
  if (!(alpha > 0) || !(interior_alpha > 0)) return Status::Error("alpha must be positive");
  if (!(fallback_frequency >= 1)) return Status::Error("the fallback frequency must be at least 1");
  return Status::Ok();
}

bool DominantFrequencies(const Image& lum, double* rows, double* columns, std::string* why) {
  const int w = lum.width(), h = lum.height();
  cv::Mat plane(h, w, CV_32F);
  double mean = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) mean += lum.at(x, y, 0);
  mean /= double(w) * h;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) plane.at<float>(y, x) = float(lum.at(x, y, 0) - mean);
  cv::Mat spectrum;
  cv::dft(plane, spectrum, cv::DFT_COMPLEX_OUTPUT);
  // Marginal amplitude per frequency index along each axis (k and -k together).
  std::vector<double> along_rows(h / 2 + 1, 0), along_columns(w / 2 + 1, 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const cv::Vec2f c = spectrum.at<cv::Vec2f>(y, x);
      const double a = std::hypot(c[0], c[1]);
      along_rows[std::min(y, h - y)] += a;
      along_columns[std::min(x, w - x)] += a;
    }
  auto dominant = [](const std::vector<double>& marginal, double* f) {
    if (marginal.size() < 3) return false;
    std::vector<double> rest(marginal.begin() + 1, marginal.end());
    const auto peak = std::max_element(rest.begin(), rest.end());
    *f = double(peak - rest.begin() + 1);
    return *peak > 2.0 * UpperMedian(rest);
  };
  const bool r = dominant(along_rows, rows), c = dominant(along_columns, columns);
  if (!r || !c) {
    *why = "no dominant low frequency: the strongest non-zero frequency is not twice the median amplitude";
    return false;
  }
  return true;
}

namespace {

// A candidate rectangle: origin in the sample, tile period, overlaps.
struct Rectangle {
  int x0 = 0, y0 = 0, tile_w = 0, tile_h = 0, h = 0, v = 0;
};

// Overlap errors of a rectangle: psi_h over the h x (tile_w + v) top band (row t against row
// t + tile_h), psi_v over the (tile_h + h) x v left band (column u against u + tile_w).
struct OverlapErrors {
  int rows_h = 0, cols_h = 0, rows_v = 0, cols_v = 0;
  std::vector<double> psi_h, psi_v;
  double H(int t, int c) const { return psi_h[size_t(t) * cols_h + c]; }
  double V(int t, int u) const { return psi_v[size_t(t) * cols_v + u]; }
};

OverlapErrors ErrorsOf(const Image& f, const Rectangle& r) {
  OverlapErrors e;
  e.rows_h = r.h, e.cols_h = r.tile_w + r.v, e.rows_v = r.tile_h + r.h, e.cols_v = r.v;
  e.psi_h.resize(size_t(e.rows_h) * e.cols_h);
  e.psi_v.resize(size_t(e.rows_v) * e.cols_v);
  const int F = f.channels();
  for (int t = 0; t < e.rows_h; ++t)
    for (int c = 0; c < e.cols_h; ++c)
      e.psi_h[size_t(t) * e.cols_h + c] = FeatureDistanceSquared(f.pixel(r.x0 + c, r.y0 + t), f.pixel(r.x0 + c, r.y0 + t + r.tile_h), F);
  for (int t = 0; t < e.rows_v; ++t)
    for (int u = 0; u < e.cols_v; ++u)
      e.psi_v[size_t(t) * e.cols_v + u] = FeatureDistanceSquared(f.pixel(r.x0 + u, r.y0 + t), f.pixel(r.x0 + u + r.tile_w, r.y0 + t), F);
  return e;
}

// Minimum-error path across `length` steps through a band `depth` wide (Haindl §2.3: each step
// moves at most one texel sideways). cost(step, offset). With start >= 0 the path starts at that
// offset and must be able to return to it after the last step (closed on the torus); otherwise
// its ends are free. Returns the total error and the offsets per step.
double CutPath(int length, int depth, const std::function<double(int, int)>& cost, int start, std::vector<int>* path) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  std::vector<double> d(size_t(length) * depth, kInf);
  std::vector<int> from(size_t(length) * depth, -1);
  for (int o = 0; o < depth; ++o)
    if (start < 0 || o == start) d[o] = cost(0, o);
  for (int s = 1; s < length; ++s)
    for (int o = 0; o < depth; ++o) {
      double best = kInf;
      int arg = -1;
      for (int p = std::max(0, o - 1); p <= std::min(depth - 1, o + 1); ++p)
        if (d[size_t(s - 1) * depth + p] < best) best = d[size_t(s - 1) * depth + p], arg = p;
      if (arg < 0) continue;
      d[size_t(s) * depth + o] = best + cost(s, o);
      from[size_t(s) * depth + o] = arg;
    }
  double best = kInf;
  int end = -1;
  for (int o = 0; o < depth; ++o)
    if ((start < 0 || std::abs(o - start) <= 1) && d[size_t(length - 1) * depth + o] < best)
      best = d[size_t(length - 1) * depth + o], end = o;
  if (path && end >= 0) {
    path->assign(length, 0);
    for (int s = length - 1, o = end; s >= 0; o = from[size_t(s) * depth + o], --s) (*path)[s] = o;
  }
  return best;
}

// The proxy used to rank rectangles: both free-ended cuts' mean error.
double RectangleCost(const Image& f, const Rectangle& r) {
  const OverlapErrors e = ErrorsOf(f, r);
  const double h = CutPath(r.tile_w, r.h, [&](int c, int t) { return e.H(t, c); }, -1, nullptr);
  const double v = CutPath(r.tile_h, r.v, [&](int t, int u) { return e.V(t, u); }, -1, nullptr);
  return h / r.tile_w + v / r.tile_h;
}

std::vector<int> Spread(int lo, int hi, int count) {
  std::vector<int> v;
  if (hi < lo) return v;
  const int n = std::min(count, hi - lo + 1);
  for (int k = 0; k < n; ++k) v.push_back(n == 1 ? lo : lo + int(std::lround(double(k) * (hi - lo) / (n - 1))));
  v.erase(std::unique(v.begin(), v.end()), v.end());
  return v;
}

// Tile period range on one axis (Haindl §2.1), clamped so the rectangle fits the sample.
bool PeriodRange(int n, double f, int overlap, int tiles, int* lo, int* hi) {
  *lo = std::max(4, int(std::ceil(n / (f + 0.5))));
  *hi = f > 0.5 ? int(std::floor(n / (f - 0.5))) : n;
  *hi = std::min(*hi, n - overlap);
  if (tiles > 1) *hi = std::min(*hi, n / tiles);
  *lo = std::max(*lo, overlap + 1);  // the overlap band lies inside one period
  return *lo <= *hi;
}

}  // namespace

StatusOr<RollerTiles> AnalyseRoller(const Image& f, const Image& lum, const RollerOptions& options, RollerReport* report) {
  MESOCAP_RETURN_IF_ERROR(options.Check());
  const auto start = std::chrono::steady_clock::now();
  RollerReport local;
  RollerReport& rep = report ? *report : local;
  rep = {};
  const int N = f.height(), M = f.width();
  std::string why;
  double fr = 0, fc = 0;
  const bool dominant = DominantFrequencies(lum, &fr, &fc, &why);
  auto ranges = [&](double fr_, double fc_, Rectangle* shape, int* lo_r, int* hi_r, int* lo_c, int* hi_c) {
    shape->h = std::max(1, int(std::lround(N / (options.alpha * fr_))));
    shape->v = std::max(1, int(std::lround(M / (options.alpha * fc_))));
    return PeriodRange(N, fr_, shape->h, options.tiles, lo_r, hi_r) && PeriodRange(M, fc_, shape->v, options.tiles, lo_c, hi_c);
  };
  Rectangle shape;
  int lo_r = 0, hi_r = 0, lo_c = 0, hi_c = 0;
  if (!dominant || !ranges(fr, fc, &shape, &lo_r, &hi_r, &lo_c, &hi_c)) {
    if (dominant) why = Format("the dominant frequencies (%g, %g) give no tile that fits the sample", fr, fc);
    rep.frequency_fallback = true;
    rep.fallback_reason = why + Format("; using f = %g on both axes", options.fallback_frequency);
    fr = fc = options.fallback_frequency;
    if (!ranges(fr, fc, &shape, &lo_r, &hi_r, &lo_c, &hi_c))
      return Status::Error(Format("the sample (%dx%d texels) is too small for a roller tile (%d tile%s)", M, N, options.tiles,
                                  options.tiles > 1 ? "s" : ""));
  }
  rep.frequency_rows = fr, rep.frequency_columns = fc;
  rep.overlap_rows = shape.h, rep.overlap_columns = shape.v;

  // The minimal inscribed rectangle: sizes in the range and positions on a grid, ranked by the
  // free cuts' mean error.
  std::vector<Rectangle> candidates;
  for (int th : Spread(lo_r, hi_r, 6))
    for (int tw : Spread(lo_c, hi_c, 6))
      for (int y0 : Spread(0, N - th - shape.h, 8))
        for (int x0 : Spread(0, M - tw - shape.v, 8)) candidates.push_back({x0, y0, tw, th, shape.h, shape.v});
  std::vector<double> costs(candidates.size());
  ParallelFor(0, int(candidates.size()), [&](int k) { costs[k] = RectangleCost(f, candidates[k]); }, options.num_threads);
  const Rectangle r = candidates[std::min_element(costs.begin(), costs.end()) - costs.begin()];

  // The optimal vertex r* in the corner overlap and the two closed cuts through it.
  const OverlapErrors e = ErrorsOf(f, r);
  double best = std::numeric_limits<double>::infinity();
  int r1 = 0, r2 = 0;
  std::vector<int> cut_h, cut_v;
  for (int t = 0; t < r.h; ++t)
    for (int u = 0; u < r.v; ++u) {
      std::vector<int> ph, pv;
      const double ch = CutPath(r.tile_w, r.h, [&](int s, int o) { return e.H(o, u + s); }, t, &ph);
      const double cv = CutPath(r.tile_h, r.v, [&](int s, int o) { return e.V(t + s, o); }, u, &pv);
      if (ch + cv < best) best = ch + cv, r1 = t, r2 = u, cut_h = ph, cut_v = pv;
    }
  rep.vertex_row = r1, rep.vertex_column = r2;
  rep.mean_cut_error = best / (r.tile_w + r.tile_h);
  rep.tile_width = r.tile_w, rep.tile_height = r.tile_h;
  rep.rectangle_x = r.x0, rep.rectangle_y = r.y0;

  // The double toroidal tile, already rectangular: tile texel (u, t) takes the bottom copy above
  // the horizontal cut and the right copy left of the vertical cut.
  RollerTiles tiles;
  tiles.tile_width = r.tile_w, tiles.tile_height = r.tile_h;
  std::vector<Eigen::Vector2i> base(size_t(r.tile_w) * r.tile_h);
  for (int t = 0; t < r.tile_h; ++t)
    for (int u = 0; u < r.tile_w; ++u) {
      const int s_u = cut_h[u >= r2 ? u - r2 : u + r.tile_w - r2];
      const int w_t = cut_v[t >= r1 ? t - r1 : t + r.tile_h - r1];
      const int row = t + (t < s_u ? r.tile_h : 0), col = u + (u < w_t ? r.tile_w : 0);
      base[size_t(t) * r.tile_w + u] = {r.x0 + col, r.y0 + row};
    }
  tiles.tiles.push_back(base);

  // Multiple tiles (Haindl §2.6): the same border, the interior from elsewhere in the sample, cut
  // in by min-cut through a band of N / (interior_alpha f) texels inside a frame as wide.
  if (options.tiles > 1) {
    const int bh = std::max(1, int(std::lround(N / (options.interior_alpha * fr))));
    const int bv = std::max(1, int(std::lround(M / (options.interior_alpha * fc))));
    // A frame of half a band keeps the borders identical; the cut runs through the next band.
    const int fh = std::max(1, bh / 2), fv = std::max(1, bv / 2);
    if (r.tile_h < 2 * (fh + bh) + 1 || r.tile_w < 2 * (fv + bv) + 1)
      return Status::Error(Format("the tile (%dx%d) is too small for an interior replacement band of %dx%d texels",
                                  r.tile_w, r.tile_h, bv, bh));
    Image tile_features(r.tile_w, r.tile_h, f.channels());
    for (int t = 0; t < r.tile_h; ++t)
      for (int u = 0; u < r.tile_w; ++u) std::copy_n(f.pixel(base[size_t(t) * r.tile_w + u].x(), base[size_t(t) * r.tile_w + u].y()),
                                                   f.channels(), tile_features.pixel(u, t));
    std::vector<uint8_t> ring(size_t(r.tile_w) * r.tile_h, 0);
    std::vector<FitFreedom> freedom(ring.size(), FitFreedom::kForceNew);
    for (int t = 0; t < r.tile_h; ++t)
      for (int u = 0; u < r.tile_w; ++u) {
        const int depth_r = std::min(t, r.tile_h - 1 - t), depth_c = std::min(u, r.tile_w - 1 - u);
        const size_t i = size_t(t) * r.tile_w + u;
        if (depth_r < fh || depth_c < fv) freedom[i] = FitFreedom::kForceOld;
        else if (depth_r < fh + bh || depth_c < fv + bv) freedom[i] = FitFreedom::kFree;
        ring[i] = freedom[i] != FitFreedom::kForceNew;
      }
    std::vector<RotatedSample> copies{MakeRotatedSample(f, Image(), 0)};
    PatchMatcher matcher(copies, {0, options.num_threads});
    MatchWindow window;
    window.width = r.tile_w, window.height = r.tile_h;
    window.features = &tile_features;
    window.synthesized = &ring;
    int vw = 0, vh = 0;
    const std::vector<double> match = matcher.Costs(window, 0, &vw, &vh);
    std::vector<Eigen::Vector2i> used{{r.x0, r.y0}};
    for (int k = 1; k < options.tiles; ++k) {
      double best_cost = std::numeric_limits<double>::infinity();
      Eigen::Vector2i best_pos(-1, -1);
      for (int y = 0; y < vh; ++y)
        for (int x = 0; x < vw; ++x) {
          bool far = true;  // not the base tile's own content nor an interior already used
          for (const auto& p : used) far &= std::abs(x - p.x()) >= r.tile_w / 2 || std::abs(y - p.y()) >= r.tile_h / 2;
          if (far && match[size_t(y) * vw + x] < best_cost) best_cost = match[size_t(y) * vw + x], best_pos = {x, y};
        }
      if (best_pos.x() < 0) break;  // the sample has no room for another distinct interior
      used.push_back(best_pos);
      rep.interior_sources.push_back(best_pos);
      SynthCanvas canvas(r.tile_w, r.tile_h, f, "roller");
      canvas.features = tile_features;
      std::fill(canvas.synthesized.begin(), canvas.synthesized.end(), 1);
      for (int t = 0; t < r.tile_h; ++t)
        for (int u = 0; u < r.tile_w; ++u) {
          const Eigen::Vector2i s = base[size_t(t) * r.tile_w + u];
          canvas.map.Set(u, t, s.x() + 0.5f, s.y() + 0.5f, 0, 0);
        }
      canvas.next_patch = 1;
      PlacedPatch patch{&copies[0], best_pos.x(), best_pos.y(), 0, 0, r.tile_w, r.tile_h};
      CommitPatch(&canvas, patch, FitPatch(canvas, patch, freedom));
      std::vector<Eigen::Vector2i> tile(base.size());
      for (int t = 0; t < r.tile_h; ++t)
        for (int u = 0; u < r.tile_w; ++u) tile[size_t(t) * r.tile_w + u] = canvas.map.SourceTexel(u, t);
      tiles.tiles.push_back(std::move(tile));
    }
  }
  rep.tiles_made = int(tiles.tiles.size());
  rep.seconds_analysis = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return tiles;
}

SynthMap RollTiles(const RollerTiles& tiles, int sample_width, int sample_height, int width, int height, uint32_t seed) {
  SynthMap map(width, height, sample_width, sample_height, "roller");
  const int cells_x = (width + tiles.tile_width - 1) / tiles.tile_width;
  const int cells_y = (height + tiles.tile_height - 1) / tiles.tile_height;
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> pick(0, int(tiles.tiles.size()) - 1);
  std::vector<int> choice(size_t(cells_x) * cells_y);
  for (int& c : choice) c = pick(rng);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const int cell = (y / tiles.tile_height) * cells_x + x / tiles.tile_width;
      const Eigen::Vector2i s =
          tiles.tiles[choice[cell]][size_t(y % tiles.tile_height) * tiles.tile_width + x % tiles.tile_width];
      map.Set(x, y, s.x() + 0.5f, s.y() + 0.5f, 0, cell);
    }
  return map;
}

StatusOr<SynthMap> RollerSynthesis(const Image& features, const Image& lum, const RollerOptions& options, RollerReport* report) {
  RollerReport local;
  RollerReport& rep = report ? *report : local;
  auto tiles = AnalyseRoller(features, lum, options, &rep);
  if (!tiles.ok()) return tiles.status();
  const auto start = std::chrono::steady_clock::now();
  SynthMap map = RollTiles(*tiles, features.width(), features.height(), options.width, options.height, options.seed);
  rep.seconds_synthesis = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return map;
}

Image TileFeatures(const RollerTiles& tiles, int k, const Image& f) {
  Image out(tiles.tile_width, tiles.tile_height, f.channels());
  for (int t = 0; t < tiles.tile_height; ++t)
    for (int u = 0; u < tiles.tile_width; ++u) {
      const Eigen::Vector2i s = tiles.tiles[k][size_t(t) * tiles.tile_width + u];
      std::copy_n(f.pixel(s.x(), s.y()), f.channels(), out.pixel(u, t));
    }
  return out;
}

}  // namespace mesocap
