#include "synth/patch_matching.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <functional>
#include <limits>
#include <memory>
#include <vector>

#include "core/directions.h"
#include "core/fftw_buffers.h"
#include "core/parallel.h"
#include "core/status.h"
#include "synth/synth_map.h"

namespace mesocap {

Eigen::Vector2d RotatedSample::SourceOf(int u, int v) const {
  return origin + RotatedStep(u, v, rotation_deg);
}

Eigen::Vector2i RotatedSample::SourceTexel(int u, int v) const {
  const Eigen::Vector2d s = SourceOf(u, v);
  return {std::clamp(int(std::floor(s.x())), 0, sample_width - 1), std::clamp(int(std::floor(s.y())), 0, sample_height - 1)};
}

RotatedSample MakeRotatedSample(const Image& features, const Image& constraint, double rotation_deg) {
  RotatedSample copy;
  copy.rotation_deg = rotation_deg;
  const int w = features.width(), h = features.height();
  copy.sample_width = w;
  copy.sample_height = h;
  if (std::fmod(std::abs(rotation_deg), 360.0) == 0) {
    copy.size_x = w;
    copy.size_y = h;
  } else {
    const double c = std::abs(std::cos(DegToRad(rotation_deg))), s = std::abs(std::sin(DegToRad(rotation_deg)));
    copy.size_x = copy.size_y = std::max(1, int(std::floor(std::min(w, h) / (c + s) - 1e-9)));
  }
  // The copy's centre sits on the sample's centre.
  copy.origin = Eigen::Vector2d(w / 2.0, h / 2.0) + RotatedStep(0.5 - copy.size_x / 2.0, 0.5 - copy.size_y / 2.0, rotation_deg);
  copy.features = Image(copy.size_x, copy.size_y, features.channels());
  if (!constraint.empty()) copy.constraint = Image(copy.size_x, copy.size_y, 1);
  for (int v = 0; v < copy.size_y; ++v)
    for (int u = 0; u < copy.size_x; ++u) {
      const Eigen::Vector2i s = copy.SourceTexel(u, v);
      const int sx = s.x(), sy = s.y();
      std::copy_n(features.pixel(sx, sy), features.channels(), copy.features.pixel(u, v));
      if (!constraint.empty()) copy.constraint.at(u, v) = constraint.at(sx, sy);
    }
  return copy;
}

namespace {
using Complex = FftComplex;

// The window texel that must land on the copy: the anchor, or the window's centre.
Eigen::Vector2i AnchorOf(const MatchWindow& w) {
  return {w.anchor_x >= 0 ? w.anchor_x : w.width / 2, w.anchor_y >= 0 ? w.anchor_y : w.height / 2};
}

// The anchor's distance from the copy's border, kept under half the copy's side.
int AnchorMargin(const RotatedSample& copy, int margin) {
  return std::clamp(margin, 0, (std::min(copy.size_x, copy.size_y) - 1) / 2);
}

// The placements leaving the copy: the window's anchor texel on the copy, `margin` texels inside
// its border.
struct LeavingRange {
  int u_min = 0, v_min = 0, width = 0, height = 0;
};
LeavingRange LeavingPlacements(const RotatedSample& copy, const MatchWindow& w, int margin) {
  margin = AnchorMargin(copy, margin);
  const Eigen::Vector2i a = AnchorOf(w);
  return {margin - a.x(), margin - a.y(), copy.size_x - 2 * margin, copy.size_y - 2 * margin};
}
using FloatBuffer = FftFloatBuffer;
using ComplexBuffer = FftComplexBuffer;

// a conj(b), written out: std::complex's operator* checks for NaN and infinities (C99 Annex G),
// which kept the spectrum products from vectorizing and took a tenth of quilting's time.
inline Complex MulConj(Complex a, Complex b) {
  return {a.real() * b.real() + a.imag() * b.imag(), a.imag() * b.real() - a.real() * b.imag()};
}

// One FFT plane size: its plans and every copy's spectra on it.
struct MatchPlane {
  int px = 0, py = 0;
  size_t spectrum = 0;
  fftwf_plan forward = nullptr, inverse = nullptr;
  // Per copy: channel spectra, spectrum of |S|^2, then of ms and of ms^2 (constrained) or of the
  // copy's indicator V (leaving).
  std::vector<std::vector<ComplexBuffer>> copy_spectra;

  MatchPlane(int width, int height) : px(width), py(height), spectrum(size_t(height) * (width / 2 + 1)) {
    const RealFftPlans& plans = RealFftPlansFor(px, py);
    forward = plans.forward;
    inverse = plans.inverse;
  }
  ComplexBuffer SpectrumOf(const std::function<float(int, int)>& value, int w, int h, int x_off = 0, int y_off = 0) const {
    FloatBuffer plane(size_t(px) * py);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) plane.data[size_t(y) * px + x] = value(x + x_off, y + y_off);
    ComplexBuffer out(spectrum);
    fftwf_execute_dft_r2c(forward, plane.data, out.fftw());
    return out;
  }
};

}  // namespace

struct PatchMatcher::Impl {
  const std::vector<RotatedSample>* copies = nullptr;
  PatchMatcherOptions options;
  int size_x = 0, size_y = 0;  // the largest copy
  int channels = 0;
  bool constrained = false;
  bool leaving = false;  // placements may leave the copy (options.max_window > 0)
  int margin = 0;        // leaving: the smallest anchor margin over the copies
  // Placements inside the copy: one plane. Leaving: planes for growing reaches (how far a window
  // texel lies from its anchor), the last for max_window / 2; plane_reach[i] is planes[i]'s.
  std::vector<std::unique_ptr<MatchPlane>> planes;
  std::vector<int> plane_reach;

  // A window reaching `reach` texels from its anchor (so at most 2 reach + 1 a side), with the
  // anchor `margin` inside the copy, touches offsets -(reach - margin) .. size + reach - margin - 1:
  // a plane this much larger keeps the circular correlation from wrapping onto the copy.
  int PlaneSide(int size, int reach) const {
    return FftFriendlySize(std::max(size + std::max(0, reach - margin), 2 * reach + 1));
  }
  std::unique_ptr<MatchPlane> MakePlane(int px, int py) const;
  const MatchPlane& PlaneFor(int reach) const {
    for (size_t i = 0; i < planes.size(); ++i)
      if (reach <= plane_reach[i]) return *planes[i];
    MESOCAP_CHECK(false, "a match window reaches farther from its anchor than max_window / 2");
    return *planes.back();
  }
};

std::unique_ptr<MatchPlane> PatchMatcher::Impl::MakePlane(int px, int py) const {
  auto plane = std::make_unique<MatchPlane>(px, py);
  const int per_copy = channels + 1 + (constrained ? 2 : 0) + (leaving ? 1 : 0);
  plane->copy_spectra.resize(copies->size());
  for (auto& list : plane->copy_spectra)
    for (int j = 0; j < per_copy; ++j) list.emplace_back(0);
  ParallelFor(0, int(copies->size()) * per_copy, [&](int job) {
    const int k = job / per_copy, j = job % per_copy;
    const RotatedSample& c = (*copies)[k];
    std::function<float(int, int)> value;
    if (j < channels) {
      value = [&c, j](int x, int y) { return c.features.at(x, y, j); };
    } else if (j == channels) {
      value = [&c](int x, int y) {
        const float* f = c.features.pixel(x, y);
        float s = 0;
        for (int i = 0; i < c.features.channels(); ++i) s += f[i] * f[i];
        return s;
      };
    } else if (leaving) {
      value = [](int, int) { return 1.f; };
    } else if (j == channels + 1) {
      value = [&c](int x, int y) { return c.constraint.at(x, y); };
    } else {
      value = [&c](int x, int y) { return c.constraint.at(x, y) * c.constraint.at(x, y); };
    }
    plane->copy_spectra[k][j] = plane->SpectrumOf(value, c.size_x, c.size_y);
  }, options.num_threads);
  return plane;
}

PatchMatcher::PatchMatcher(const std::vector<RotatedSample>& copies, const PatchMatcherOptions& options)
    : impl_(std::make_unique<Impl>()) {
  MESOCAP_CHECK(!copies.empty(), "no sample copies to match against");
  Impl& m = *impl_;
  m.copies = &copies;
  m.options = options;
  m.channels = copies[0].features.channels();
  m.leaving = options.max_window > 0;
  MESOCAP_CHECK(!(m.leaving && options.constraint_weight > 0), "placements leaving the copy take no constraint term");
  m.constrained = options.constraint_weight > 0 && !copies[0].constraint.empty();
  for (const auto& c : copies) {
    m.size_x = std::max(m.size_x, c.size_x);
    m.size_y = std::max(m.size_y, c.size_y);
  }
  if (!m.leaving) {
    m.planes.push_back(m.MakePlane(FftFriendlySize(m.size_x), FftFriendlySize(m.size_y)));
    m.plane_reach.push_back(std::numeric_limits<int>::max());
    return;
  }
  m.margin = std::numeric_limits<int>::max();
  for (const auto& c : copies) m.margin = std::min(m.margin, AnchorMargin(c, options.anchor_margin));
  // Three planes: windows within the margin (they stay on the copy: no padding), up to halfway to
  // max_window / 2, and the rest. Quilting shrinks most of its windows (r_w x 0.8^k): on a 128-texel
  // sample with r_w 32 the planes are 128, 144 and 160 texels a side, where one plane for every
  // window would be 160 (and 192 with padding by the whole window).
  const int largest = options.max_window / 2;
  for (int reach : {std::min(m.margin, largest), std::min((m.margin + largest) / 2, largest), largest}) {
    const int px = m.PlaneSide(m.size_x, reach), py = m.PlaneSide(m.size_y, reach);
    if (!m.planes.empty() && m.planes.back()->px == px && m.planes.back()->py == py) {
      m.plane_reach.back() = reach;  // a larger reach fits the same plane
      continue;
    }
    m.planes.push_back(m.MakePlane(px, py));
    m.plane_reach.push_back(reach);
  }
}

PatchMatcher::~PatchMatcher() = default;

struct PatchMatcher::WindowSpectra {
  std::vector<ComplexBuffer> masked_features;  // F(M O_c), per channel
  ComplexBuffer mask{0};                       // F(M)
  ComplexBuffer target{0}, box{0};             // F(m0 over the window), F(window indicator)
  ComplexBuffer masked_norms{0};               // F(M |O|^2), for placements leaving the copy
  const MatchPlane* plane = nullptr;           // the plane the spectra are on
  double masked_norm = 0, target_norm = 0;     // sum M |O|^2, sum m0^2
  double overlap = 0, area = 0;
  bool use_constraint = false;
};

std::unique_ptr<PatchMatcher::WindowSpectra> PatchMatcher::Prepare(const MatchWindow& w) const {
  const Impl& m = *impl_;
  // A window larger than every copy has no placement, and would overflow the FFT planes.
  if (m.leaving ? std::max(w.width, w.height) > m.options.max_window : w.width > m.size_x || w.height > m.size_y) return nullptr;
  const Image& out = *w.features;
  const std::vector<uint8_t>& syn = *w.synthesized;
  auto masked = [&](int x, int y) { return syn[size_t(y) * out.width() + x] != 0; };
  auto ws = std::make_unique<WindowSpectra>();
  const Eigen::Vector2i a = AnchorOf(w);
  ws->plane = &m.PlaneFor(std::max({a.x(), w.width - 1 - a.x(), a.y(), w.height - 1 - a.y()}));
  ws->area = double(w.width) * w.height;
  for (int y = 0; y < w.height; ++y)
    for (int x = 0; x < w.width; ++x)
      if (masked(w.x0 + x, w.y0 + y)) {
        ws->overlap += 1;
        const float* f = out.pixel(w.x0 + x, w.y0 + y);
        for (int c = 0; c < m.channels; ++c) ws->masked_norm += double(f[c]) * f[c];
      }
  ws->use_constraint = m.constrained && w.target_constraint;
  if (ws->use_constraint)
    for (int y = 0; y < w.height; ++y)
      for (int x = 0; x < w.width; ++x) ws->target_norm += std::pow(double(w.target_constraint->at(w.x0 + x, w.y0 + y)), 2);
  const int jobs = m.channels + 1 + (ws->use_constraint ? 2 : 0) + (m.leaving ? 1 : 0);
  for (int c = 0; c < m.channels; ++c) ws->masked_features.emplace_back(0);
  ParallelFor(0, jobs, [&](int j) {
    std::function<float(int, int)> value;
    if (j < m.channels)
      value = [&, j](int x, int y) { return masked(x, y) ? out.at(x, y, j) : 0.f; };
    else if (j == m.channels)
      value = [&](int x, int y) { return masked(x, y) ? 1.f : 0.f; };
    else if (m.leaving)
      value = [&](int x, int y) {
        if (!masked(x, y)) return 0.f;
        const float* f = out.pixel(x, y);
        float n = 0;
        for (int c = 0; c < m.channels; ++c) n += f[c] * f[c];
        return n;
      };
    else if (j == m.channels + 1)
      value = [&](int x, int y) { return w.target_constraint->at(x, y); };
    else
      value = [](int, int) { return 1.f; };
    ComplexBuffer s = ws->plane->SpectrumOf(value, w.width, w.height, w.x0, w.y0);
    if (j < m.channels) ws->masked_features[j] = std::move(s);
    else if (j == m.channels) ws->mask = std::move(s);
    else if (m.leaving) ws->masked_norms = std::move(s);
    else if (j == m.channels + 1) ws->target = std::move(s);
    else ws->box = std::move(s);
  }, m.options.num_threads);
  return ws;
}

std::vector<double> PatchMatcher::CostsFor(const MatchWindow& w, const WindowSpectra& ws, int copy_index, int* valid_w,
                                           int* valid_h, int* u_min, int* v_min) const {
  const Impl& m = *impl_;
  if (m.leaving) return LeavingCostsFor(w, ws, copy_index, valid_w, valid_h, u_min, v_min);
  *u_min = *v_min = 0;
  const RotatedSample& copy = (*m.copies)[copy_index];
  *valid_w = copy.size_x - w.width + 1;
  *valid_h = copy.size_y - w.height + 1;
  if (*valid_w <= 0 || *valid_h <= 0) return {};
  // cost spectrum = (F(|S|^2) conj F(M) - 2 sum_c F(S_c) conj F(M O_c)) / overlap
  //               + lambda (F(ms^2) conj F(box) - 2 F(ms) conj F(m0)) / area
  const MatchPlane& p = *ws.plane;
  const auto& spectra = p.copy_spectra[copy_index];
  ComplexBuffer total(p.spectrum);
  const float inv_overlap = ws.overlap > 0 ? float(1.0 / ws.overlap) : 0.f;
  const double weight = m.options.constraint_weight * w.constraint_scale;
  const float lambda = ws.use_constraint ? float(weight / ws.area) : 0.f;
  for (size_t i = 0; i < p.spectrum; ++i) {
    Complex cross(0);
    for (int c = 0; c < m.channels; ++c) cross += MulConj(spectra[c].data[i], ws.masked_features[c].data[i]);
    Complex t = (MulConj(spectra[m.channels].data[i], ws.mask.data[i]) - 2.f * cross) * inv_overlap;
    if (ws.use_constraint)
      t += lambda * (MulConj(spectra[m.channels + 2].data[i], ws.box.data[i]) -
                     2.f * MulConj(spectra[m.channels + 1].data[i], ws.target.data[i]));
    total.data[i] = t;
  }
  FloatBuffer plane(size_t(p.px) * p.py);
  fftwf_execute_dft_c2r(p.inverse, reinterpret_cast<fftwf_complex*>(total.data), plane.data);
  const double scale = 1.0 / (double(p.px) * p.py);
  const double constant = (ws.overlap > 0 ? ws.masked_norm / ws.overlap : 0) +
                          (ws.use_constraint ? weight * ws.target_norm / ws.area : 0);
  std::vector<double> costs(size_t(*valid_w) * *valid_h);
  for (int v = 0; v < *valid_h; ++v)
    for (int u = 0; u < *valid_w; ++u)
      costs[size_t(v) * *valid_w + u] = std::max(0.0, constant + plane.data[size_t(v) * p.px + u] * scale);
  return costs;
}

// cost(t) = (SSD over the covered texels + c x the uncovered ones) / overlap, with the covered SSD
// sum_p M V(p + t) |O|^2 - 2 sum_p M O.S(p + t) + sum_p M |S|^2(p + t) (S and |S|^2 being 0 off the
// copy, V its indicator) and the uncovered count overlap - sum_p M V(p + t): linear in the
// correlations, so one inverse FFT, as for placements inside the copy.
std::vector<double> PatchMatcher::LeavingCostsFor(const MatchWindow& w, const WindowSpectra& ws, int copy_index, int* valid_w,
                                                  int* valid_h, int* u_min, int* v_min) const {
  const Impl& m = *impl_;
  const RotatedSample& copy = (*m.copies)[copy_index];
  const LeavingRange range = LeavingPlacements(copy, w, m.options.anchor_margin);
  *u_min = range.u_min, *v_min = range.v_min, *valid_w = range.width, *valid_h = range.height;
  const MatchPlane& p = *ws.plane;
  const auto& spectra = p.copy_spectra[copy_index];
  const ComplexBuffer& indicator = spectra[m.channels + 1];
  const float c = float(m.options.uncovered_cost);
  ComplexBuffer total(p.spectrum);
  for (size_t i = 0; i < p.spectrum; ++i) {
    Complex cross(0);
    for (int k = 0; k < m.channels; ++k) cross += MulConj(spectra[k].data[i], ws.masked_features[k].data[i]);
    total.data[i] = MulConj(spectra[m.channels].data[i], ws.mask.data[i]) - 2.f * cross +
                    MulConj(indicator.data[i], ws.masked_norms.data[i] - c * ws.mask.data[i]);
  }
  FloatBuffer plane(size_t(p.px) * p.py);
  fftwf_execute_dft_c2r(p.inverse, reinterpret_cast<fftwf_complex*>(total.data), plane.data);
  const double scale = 1.0 / (double(p.px) * p.py), inv_overlap = ws.overlap > 0 ? 1.0 / ws.overlap : 0;
  std::vector<double> costs(size_t(*valid_w) * *valid_h);
  for (int j = 0; j < *valid_h; ++j) {
    const float* row = plane.data + size_t((*v_min + j + p.py) % p.py) * p.px;
    for (int i = 0; i < *valid_w; ++i) {
      const int u = *u_min + i;  // negative offsets wrap to the plane's end
      costs[size_t(j) * *valid_w + i] = std::max(0.0, row[u < 0 ? u + p.px : u] * scale + c * ws.overlap) * inv_overlap;
    }
  }
  return costs;
}

std::vector<double> PatchMatcher::Costs(const MatchWindow& w, int copy_index, int* valid_w, int* valid_h, int* u_min,
                                        int* v_min) const {
  int ignored_u = 0, ignored_v = 0;
  if (!u_min) u_min = &ignored_u;
  if (!v_min) v_min = &ignored_v;
  const auto ws = Prepare(w);
  if (!ws) {
    *valid_w = *valid_h = *u_min = *v_min = 0;
    return {};
  }
  return CostsFor(w, *ws, copy_index, valid_w, valid_h, u_min, v_min);
}

struct PatchMatcher::AllCosts {
  std::vector<std::vector<double>> costs;  // per copy, row-major over its valid placements
  std::vector<int> widths, heights, u_min, v_min;
  MatchResult At(int k, size_t i) const {
    return MatchResult{k, u_min[k] + int(i % widths[k]), v_min[k] + int(i / widths[k]), costs[k][i], true};
  }
  MatchResult Best() const {  // the first copy and texel win ties: independent of the thread count
    MatchResult best;
    for (size_t k = 0; k < costs.size(); ++k)
      for (size_t i = 0; i < costs[k].size(); ++i)
        if (!best.found || costs[k][i] < best.cost) best = At(int(k), i);
    return best;
  }
};

bool PatchMatcher::CostsOfAll(const MatchWindow& window, AllCosts* all) const {
  const Impl& m = *impl_;
  const int n = int(m.copies->size());
  const auto ws = Prepare(window);
  if (!ws) return false;
  all->costs.assign(n, {});
  all->widths.assign(n, 0), all->heights.assign(n, 0), all->u_min.assign(n, 0), all->v_min.assign(n, 0);
  ParallelFor(0, n, [&](int k) {
    all->costs[k] = CostsFor(window, *ws, k, &all->widths[k], &all->heights[k], &all->u_min[k], &all->v_min[k]);
  }, n > 1 ? m.options.num_threads : 1);
  return true;
}

MatchResult PatchMatcher::ChooseMatch(const MatchWindow& window, double temperature, double uniform) const {
  AllCosts all;
  if (!CostsOfAll(window, &all)) return {};
  const MatchResult best = all.Best();
  if (!best.found || temperature <= 0) return best;
  double total = 0;
  for (const auto& c : all.costs)
    for (double v : c) total += std::exp(-(v - best.cost) / temperature);
  double target = uniform * total;
  for (size_t k = 0; k < all.costs.size(); ++k)
    for (size_t i = 0; i < all.costs[k].size(); ++i) {
      target -= std::exp(-(all.costs[k][i] - best.cost) / temperature);
      if (target <= 0) return all.At(int(k), i);
    }
  return best;
}

MatchResult PatchMatcher::ChooseNearBest(const MatchWindow& window, double tolerance, double floor,
                                         const std::function<double(const MatchResult&)>& key) const {
  AllCosts all;
  if (!CostsOfAll(window, &all)) return {};
  const MatchResult best = all.Best();
  if (!best.found) return best;
  const double limit = best.cost * (1 + tolerance) + floor;
  MatchResult chosen = best;
  double least = key(best);
  for (size_t k = 0; k < all.costs.size(); ++k)
    for (size_t i = 0; i < all.costs[k].size(); ++i) {
      if (all.costs[k][i] > limit) continue;
      const MatchResult candidate = all.At(int(k), i);
      const double value = key(candidate);
      if (value < least) least = value, chosen = candidate;
    }
  return chosen;
}

std::vector<double> BruteForceCosts(const RotatedSample& copy, const MatchWindow& w, double constraint_weight,
                                    int* valid_w, int* valid_h) {
  *valid_w = copy.size_x - w.width + 1;
  *valid_h = copy.size_y - w.height + 1;
  if (*valid_w <= 0 || *valid_h <= 0) return {};
  const Image& out = *w.features;
  const int channels = out.channels();
  const bool use_constraint = constraint_weight > 0 && w.target_constraint && !copy.constraint.empty();
  double overlap = 0;
  for (int y = 0; y < w.height; ++y)
    for (int x = 0; x < w.width; ++x) overlap += (*w.synthesized)[size_t(w.y0 + y) * out.width() + w.x0 + x] != 0;
  const double area = double(w.width) * w.height;
  std::vector<double> costs(size_t(*valid_w) * *valid_h);
  for (int v = 0; v < *valid_h; ++v)
    for (int u = 0; u < *valid_w; ++u) {
      double ssd = 0, constraint = 0;
      for (int y = 0; y < w.height; ++y)
        for (int x = 0; x < w.width; ++x) {
          const int ox = w.x0 + x, oy = w.y0 + y;
          if ((*w.synthesized)[size_t(oy) * out.width() + ox]) {
            const float* a = out.pixel(ox, oy);
            const float* b = copy.features.pixel(u + x, v + y);
            for (int c = 0; c < channels; ++c) ssd += double(a[c] - b[c]) * (a[c] - b[c]);
          }
          if (use_constraint) constraint += std::pow(double(w.target_constraint->at(ox, oy)) - copy.constraint.at(u + x, v + y), 2);
        }
      costs[size_t(v) * *valid_w + u] = (overlap > 0 ? ssd / overlap : 0) + (use_constraint ? constraint_weight * constraint / area : 0);
    }
  return costs;
}

std::vector<double> BruteForceLeavingCosts(const RotatedSample& copy, const MatchWindow& w, double uncovered_cost,
                                           int anchor_margin, int* valid_w, int* valid_h, int* u_min, int* v_min) {
  const LeavingRange range = LeavingPlacements(copy, w, anchor_margin);
  *u_min = range.u_min, *v_min = range.v_min, *valid_w = range.width, *valid_h = range.height;
  const Image& out = *w.features;
  auto synthesized = [&](int x, int y) { return (*w.synthesized)[size_t(w.y0 + y) * out.width() + w.x0 + x] != 0; };
  double overlap = 0;
  for (int y = 0; y < w.height; ++y)
    for (int x = 0; x < w.width; ++x) overlap += synthesized(x, y);
  std::vector<double> costs(size_t(*valid_w) * *valid_h, 0.0);
  for (int j = 0; j < *valid_h; ++j)
    for (int i = 0; i < *valid_w; ++i) {
      const int u = *u_min + i, v = *v_min + j;
      double ssd = 0, n = 0;
      for (int y = 0; y < w.height; ++y)
        for (int x = 0; x < w.width; ++x) {
          const int cu = u + x, cv = v + y;
          if (!synthesized(x, y) || cu < 0 || cv < 0 || cu >= copy.size_x || cv >= copy.size_y) continue;
          const float* a = out.pixel(w.x0 + x, w.y0 + y);
          const float* b = copy.features.pixel(cu, cv);
          for (int c = 0; c < out.channels(); ++c) ssd += double(a[c] - b[c]) * (a[c] - b[c]);
          n += 1;
        }
      if (overlap > 0) costs[size_t(j) * *valid_w + i] = (ssd + (overlap - n) * uncovered_cost) / overlap;
    }
  return costs;
}

}  // namespace mesocap
