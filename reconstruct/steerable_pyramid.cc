// Frequency-domain steerable pyramid (Portilla & Simoncelli's buildSFpyr construction).
//
// Frequencies are normalised per grid: f = k / (n / 2) along each axis, so |f| = 1 is the grid's
// Nyquist frequency and r = |f| is isotropic in cycles per texel. The masks are
//   hi0(r) = cos(pi/2 * clamp(log2 r, -1, 0))       0 for r <= 1/2, 1 for r >= 1
//   lo0(r) = cos(pi/2 * (clamp(log2 r, -1, 0) + 1)) hi0^2 + lo0^2 = 1
//   band b of K at a level: hi0(2r) * sqrt(C) * cos^(K-1)(theta - pi b / K) * (-i)^(K-1),
//   with C = 4^(K-1) ((K-1)!)^2 / (K (2K-2)!) so that the K angular masks' squares sum to one,
//   theta = atan2(f_y, f_x) (f_y along rows, i.e. downwards).
// A level's low-pass is its input times lo0(2r); it is zero from half the grid's Nyquist on, so
// cropping the spectrum to half size loses nothing, and on the half-size grid the same mask is
// lo0(r). Every mask is Hermitian (radial masks are even, cos^(K-1) times (-i)^(K-1) is
// Hermitian), so every band is real, and together the masks square-sum to one: a tight frame.
// Transforms are unitary ("ortho" scaling: forward and inverse both scaled by 1/sqrt(n)), so the
// energy of the bands equals the energy of the input with unit weights, and the collapse (the
// adjoint of the build) is its exact inverse.
//
// Implementation: real-to-complex FFTW (single precision) on half spectra; the plans are shared
// (RealFftPlansFor), the masks cached per grid size under a mutex, and both executed with the
// new-array functions on per-thread, fftwf_malloc'd scratch buffers, so several threads may build
// and collapse at once.
#include "reconstruct/steerable_pyramid.h"

#include <fftw3.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "core/fftw_buffers.h"

namespace mesocap {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Largest supported orientation count (cos^(K-1) masks get very narrow beyond it).
constexpr int kMaxOrientations = 16;

// The radial raised-cosine pair at normalised radius r.
void RadialMasks(double r, double* hi, double* lo) {
  if (r <= 0.5) {
    *hi = 0, *lo = 1;
  } else if (r >= 1) {
    *hi = 1, *lo = 0;
  } else {
    const double t = std::log2(r);  // in (-1, 0)
    *hi = std::cos(kPi / 2 * t);
    *lo = std::cos(kPi / 2 * (t + 1));
  }
}

// Signed frequency of spectrum row y of a grid with n rows (the Nyquist row, if any, negative).
int SignedFrequency(int y, int n) { return y < (n + 1) / 2 ? y : y - n; }

// One grid size: its FFT plans (RealFftPlansFor) and the radial masks on its half spectrum (rows x (width/2+1)).
struct Grid {
  int width = 0, height = 0, half_width = 0;
  size_t real_size() const { return size_t(width) * height; }
  size_t spectrum_size() const { return size_t(half_width) * height; }
  fftwf_plan forward = nullptr;  // r2c, out of place
  fftwf_plan inverse = nullptr;  // c2r, out of place, destroys its input
  std::vector<float> hi0, lo0;
};

// The oriented band-pass masks of one grid size for K orientations (real part; the phase
// (-i)^(K-1) is applied separately).
struct OrientedMasks {
  std::vector<std::vector<float>> band;
  float phase_re = 1, phase_im = 0;
};

struct Cache {
  std::mutex mutex;
  std::map<std::pair<int, int>, std::unique_ptr<Grid>> grids;
  std::map<std::tuple<int, int, int>, std::unique_ptr<OrientedMasks>> masks;
};

// Never destroyed: plans stay valid for threads still running at exit.
Cache& GetCache() {
  static Cache* cache = new Cache;
  return *cache;
}

void FillFrequencies(int width, int height, int half_width, std::vector<double>* fx, std::vector<double>* fy) {
  fx->resize(half_width);
  fy->resize(height);
  for (int x = 0; x < half_width; ++x) (*fx)[x] = x / (width / 2.0);
  for (int y = 0; y < height; ++y) (*fy)[y] = SignedFrequency(y, height) / (height / 2.0);
}

// Called with the cache mutex held.
const Grid* GetGridLocked(Cache& cache, int width, int height) {
  auto& slot = cache.grids[{width, height}];
  if (slot) return slot.get();
  auto grid = std::make_unique<Grid>();
  grid->width = width;
  grid->height = height;
  grid->half_width = width / 2 + 1;
  const RealFftPlans& plans = RealFftPlansFor(width, height);
  grid->forward = plans.forward;
  grid->inverse = plans.inverse;

  std::vector<double> fx, fy;
  FillFrequencies(width, height, grid->half_width, &fx, &fy);
  grid->hi0.resize(grid->spectrum_size());
  grid->lo0.resize(grid->spectrum_size());
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < grid->half_width; ++x) {
      double hi, lo;
      RadialMasks(std::hypot(fx[x], fy[y]), &hi, &lo);
      grid->hi0[size_t(y) * grid->half_width + x] = float(hi);
      grid->lo0[size_t(y) * grid->half_width + x] = float(lo);
    }
  }
  slot = std::move(grid);
  return slot.get();
}

const OrientedMasks* GetMasksLocked(Cache& cache, int width, int height, int orientations) {
  auto& slot = cache.masks[{width, height, orientations}];
  if (slot) return slot.get();
  auto masks = std::make_unique<OrientedMasks>();
  const int half_width = width / 2 + 1;
  const int order = orientations - 1;
  const double log_c = 2 * order * std::log(2.0) + 2 * std::lgamma(order + 1.0) - std::log(double(orientations)) -
                       std::lgamma(2 * order + 1.0);
  const double amplitude = std::exp(0.5 * log_c);
  static constexpr float kPhase[4][2] = {{1, 0}, {0, -1}, {-1, 0}, {0, 1}};  // (-i)^order
  masks->phase_re = kPhase[order % 4][0];
  masks->phase_im = kPhase[order % 4][1];

  std::vector<double> fx, fy;
  FillFrequencies(width, height, half_width, &fx, &fy);
  masks->band.assign(orientations, std::vector<float>(size_t(half_width) * height));
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < half_width; ++x) {
      double band_pass, unused;
      RadialMasks(2 * std::hypot(fx[x], fy[y]), &band_pass, &unused);
      if (band_pass == 0) continue;  // also the DC term, where the angle is undefined
      const double theta = std::atan2(fy[y], fx[x]);
      for (int b = 0; b < orientations; ++b) {
        const double c = std::cos(theta - kPi * b / orientations);
        masks->band[b][size_t(y) * half_width + x] = float(band_pass * amplitude * std::pow(c, order));
      }
    }
  }
  slot = std::move(masks);
  return slot.get();
}

// What a build or collapse needs at level l (grid width>>l x height>>l); level `levels` holds
// the low-pass residual.
struct Level {
  const Grid* grid = nullptr;
  const OrientedMasks* masks = nullptr;  // null at the residual level
};

std::vector<Level> SetUp(int width, int height, int levels, int orientations) {
  Cache& cache = GetCache();
  std::lock_guard<std::mutex> lock(cache.mutex);
  std::vector<Level> setup(levels + 1);
  for (int l = 0; l <= levels; ++l) {
    setup[l].grid = GetGridLocked(cache, width >> l, height >> l);
    if (l < levels) setup[l].masks = GetMasksLocked(cache, width >> l, height >> l, orientations);
  }
  return setup;
}

// Per-thread FFTW-aligned scratch: one real plane and three half spectra of the largest grid.
struct Workspace {
  size_t real_capacity = 0, spectrum_capacity = 0;
  float* real = nullptr;
  fftwf_complex* spectrum[3] = {nullptr, nullptr, nullptr};

  void Reserve(size_t real_size, size_t spectrum_size) {
    if (real_size > real_capacity) {
      fftwf_free(real);
      real = fftwf_alloc_real(real_size);
      real_capacity = real ? real_size : 0;
      if (!real) throw std::bad_alloc();
    }
    if (spectrum_size > spectrum_capacity) {
      spectrum_capacity = 0;
      for (fftwf_complex*& s : spectrum) {
        fftwf_free(s);
        s = fftwf_alloc_complex(spectrum_size);
        if (!s) throw std::bad_alloc();
      }
      spectrum_capacity = spectrum_size;
    }
  }
  ~Workspace() {
    fftwf_free(real);
    for (fftwf_complex* s : spectrum) fftwf_free(s);
  }
};

Workspace& ThreadWorkspace(const Grid& top) {
  thread_local Workspace workspace;
  workspace.Reserve(top.real_size(), top.spectrum_size());
  return workspace;
}

// dst = src * mask * (phase_re + i phase_im) * scale, over n complex values.
void MultiplyMask(const fftwf_complex* src, const float* mask, float phase_re, float phase_im, float scale,
                  fftwf_complex* dst, size_t n) {
  for (size_t k = 0; k < n; ++k) {
    const float m = mask[k] * scale;
    const float re = src[k][0], im = src[k][1];
    dst[k][0] = m * (re * phase_re - im * phase_im);
    dst[k][1] = m * (re * phase_im + im * phase_re);
  }
}

// dst += src * mask * (phase_re + i phase_im) * scale.
void AccumulateMask(const fftwf_complex* src, const float* mask, float phase_re, float phase_im, float scale,
                    fftwf_complex* dst, size_t n) {
  for (size_t k = 0; k < n; ++k) {
    const float m = mask[k] * scale;
    const float re = src[k][0], im = src[k][1];
    dst[k][0] += m * (re * phase_re - im * phase_im);
    dst[k][1] += m * (re * phase_im + im * phase_re);
  }
}

// child = lo0(child grid) * (the child grid's frequencies of parent).
void CropSpectrum(const Grid& parent, const fftwf_complex* src, const Grid& child, fftwf_complex* dst) {
  for (int y = 0; y < child.height; ++y) {
    const int ky = SignedFrequency(y, child.height);
    const int py = ky >= 0 ? ky : ky + parent.height;
    const fftwf_complex* s = src + size_t(py) * parent.half_width;
    fftwf_complex* d = dst + size_t(y) * child.half_width;
    const float* m = child.lo0.data() + size_t(y) * child.half_width;
    for (int x = 0; x < child.half_width; ++x) {
      d[x][0] = s[x][0] * m[x];
      d[x][1] = s[x][1] * m[x];
    }
  }
}

// The adjoint of CropSpectrum: parent = zero-padded lo0(child grid) * child.
void PadSpectrum(const Grid& child, const fftwf_complex* src, const Grid& parent, fftwf_complex* dst) {
  std::memset(static_cast<void*>(dst), 0, sizeof(fftwf_complex) * parent.spectrum_size());
  for (int y = 0; y < child.height; ++y) {
    const int ky = SignedFrequency(y, child.height);
    const int py = ky >= 0 ? ky : ky + parent.height;
    const fftwf_complex* s = src + size_t(y) * child.half_width;
    fftwf_complex* d = dst + size_t(py) * parent.half_width;
    const float* m = child.lo0.data() + size_t(y) * child.half_width;
    for (int x = 0; x < child.half_width; ++x) {
      d[x][0] = s[x][0] * m[x];
      d[x][1] = s[x][1] * m[x];
    }
  }
}

int ResolveLevels(int width, int height, const SteerablePyramidOptions& options) {
  if (!options.Check())
    throw std::invalid_argument("steerable pyramid: invalid options (orientations " +
                                std::to_string(options.orientations) + ", levels " + std::to_string(options.levels) +
                                ")");
  if (width <= 0 || height <= 0)
    throw std::invalid_argument("steerable pyramid: plane size " + std::to_string(width) + "x" +
                                std::to_string(height) + " is empty");
  const int levels = options.levels < 0 ? MaxPyramidLevels(width, height) : options.levels;
  if (width % (1 << levels) != 0 || height % (1 << levels) != 0)
    throw std::invalid_argument("steerable pyramid: plane size " + std::to_string(width) + "x" +
                                std::to_string(height) + " is not divisible by 2^" + std::to_string(levels));
  return levels;
}

// Copies an FFTW real plane into a band.
void StoreBand(const float* real, int width, int height, PyramidBand* band) {
  band->width = width;
  band->height = height;
  band->values.assign(real, real + size_t(width) * height);
}

}  // namespace

bool SteerablePyramidOptions::Check() const {
  return orientations >= 1 && orientations <= kMaxOrientations && levels >= -1 && levels <= 30;
}

int MaxPyramidLevels(int width, int height) {
  if (width <= 0 || height <= 0)
    throw std::invalid_argument("MaxPyramidLevels: size " + std::to_string(width) + "x" + std::to_string(height));
  int levels = 0;
  while (levels < 30) {
    const int next = levels + 1;
    if (width % (1 << next) != 0 || height % (1 << next) != 0) break;
    if (std::min(width, height) >> next < 8) break;
    levels = next;
  }
  return levels;
}

SteerablePyramid BuildSteerablePyramid(const float* plane, int width, int height,
                                       const SteerablePyramidOptions& options) {
  const int levels = ResolveLevels(width, height, options);
  if (plane == nullptr) throw std::invalid_argument("steerable pyramid: null plane");
  const int orientations = options.orientations;
  const std::vector<Level> setup = SetUp(width, height, levels, orientations);
  const Grid& top = *setup[0].grid;
  Workspace& ws = ThreadWorkspace(top);
  fftwf_complex* spectrum = ws.spectrum[0];  // the input's spectrum, then scratch
  fftwf_complex* low = ws.spectrum[1];       // the current level's low-pass
  fftwf_complex* band = ws.spectrum[2];      // input of a c2r (destroyed)

  SteerablePyramid pyramid;
  pyramid.width = width;
  pyramid.height = height;
  pyramid.levels = levels;
  pyramid.orientations = orientations;
  pyramid.bands.resize(2 + size_t(levels) * orientations);

  std::memcpy(ws.real, plane, sizeof(float) * top.real_size());
  fftwf_execute_dft_r2c(top.forward, ws.real, spectrum);

  // Unitary scaling: forward 1/sqrt(n0); each band's inverse 1/sqrt(n_l).
  const double n0 = double(top.real_size());
  {
    const size_t n = top.spectrum_size();
    const float hi_scale = float(1 / n0), lo_scale = float(1 / std::sqrt(n0));
    for (size_t k = 0; k < n; ++k) {
      const float re = spectrum[k][0], im = spectrum[k][1];
      const float h = top.hi0[k] * hi_scale, l = top.lo0[k] * lo_scale;
      band[k][0] = re * h, band[k][1] = im * h;
      low[k][0] = re * l, low[k][1] = im * l;
    }
    fftwf_execute_dft_c2r(top.inverse, band, ws.real);
    StoreBand(ws.real, width, height, &pyramid.bands[0]);
  }

  for (int l = 0; l < levels; ++l) {
    const Grid& grid = *setup[l].grid;
    const OrientedMasks& masks = *setup[l].masks;
    const float scale = float(1 / std::sqrt(double(grid.real_size())));
    for (int b = 0; b < orientations; ++b) {
      MultiplyMask(low, masks.band[b].data(), masks.phase_re, masks.phase_im, scale, band, grid.spectrum_size());
      fftwf_execute_dft_c2r(grid.inverse, band, ws.real);
      StoreBand(ws.real, grid.width, grid.height, &pyramid.bands[1 + size_t(l) * orientations + b]);
    }
    CropSpectrum(grid, low, *setup[l + 1].grid, spectrum);
    std::swap(low, spectrum);
  }

  const Grid& residual = *setup[levels].grid;
  const float scale = float(1 / std::sqrt(double(residual.real_size())));
  for (size_t k = 0; k < residual.spectrum_size(); ++k) band[k][0] = low[k][0] * scale, band[k][1] = low[k][1] * scale;
  fftwf_execute_dft_c2r(residual.inverse, band, ws.real);
  StoreBand(ws.real, residual.width, residual.height, &pyramid.bands.back());
  return pyramid;
}

std::vector<float> CollapseSteerablePyramid(const SteerablePyramid& pyramid) {
  SteerablePyramidOptions options;
  options.orientations = pyramid.orientations;
  options.levels = pyramid.levels;
  const int width = pyramid.width, height = pyramid.height;
  const int levels = ResolveLevels(width, height, options);
  const int orientations = pyramid.orientations;
  if (pyramid.band_count() != 2 + levels * orientations)
    throw std::invalid_argument("steerable pyramid: " + std::to_string(pyramid.band_count()) + " bands, expected " +
                                std::to_string(2 + levels * orientations));
  for (int i = 0; i < pyramid.band_count(); ++i) {
    const int l = i == 0 ? 0 : std::min(levels, (i - 1) / orientations);
    const PyramidBand& band = pyramid.bands[i];
    if (band.width != width >> l || band.height != height >> l ||
        band.values.size() != size_t(band.width) * band.height)
      throw std::invalid_argument("steerable pyramid: band " + std::to_string(i) + " has the wrong size");
  }

  const std::vector<Level> setup = SetUp(width, height, levels, orientations);
  const Grid& top = *setup[0].grid;
  Workspace& ws = ThreadWorkspace(top);
  fftwf_complex* low = ws.spectrum[0];    // the reconstructed low-pass of the current level
  fftwf_complex* next = ws.spectrum[1];   // the same one level up
  fftwf_complex* band = ws.spectrum[2];   // a band's spectrum

  auto forward = [&](const Grid& grid, const PyramidBand& b, fftwf_complex* out) {
    std::memcpy(ws.real, b.values.data(), sizeof(float) * grid.real_size());
    fftwf_execute_dft_r2c(grid.forward, ws.real, out);
  };

  {
    const Grid& residual = *setup[levels].grid;
    forward(residual, pyramid.bands.back(), low);
    const float scale = float(1 / std::sqrt(double(residual.real_size())));
    for (size_t k = 0; k < residual.spectrum_size(); ++k) low[k][0] *= scale, low[k][1] *= scale;
  }
  for (int l = levels - 1; l >= 0; --l) {
    const Grid& grid = *setup[l].grid;
    const OrientedMasks& masks = *setup[l].masks;
    PadSpectrum(*setup[l + 1].grid, low, grid, next);
    std::swap(low, next);
    const float scale = float(1 / std::sqrt(double(grid.real_size())));
    for (int b = 0; b < orientations; ++b) {
      forward(grid, pyramid.bands[1 + size_t(l) * orientations + b], band);
      // The adjoint multiplies by the conjugate phase.
      AccumulateMask(band, masks.band[b].data(), masks.phase_re, -masks.phase_im, scale, low, grid.spectrum_size());
    }
  }

  forward(top, pyramid.bands[0], band);
  const double n0 = double(top.real_size());
  const float hi_scale = float(1 / n0), lo_scale = float(1 / std::sqrt(n0));
  for (size_t k = 0; k < top.spectrum_size(); ++k) {
    const float h = top.hi0[k] * hi_scale, l = top.lo0[k] * lo_scale;
    band[k][0] = band[k][0] * h + low[k][0] * l;
    band[k][1] = band[k][1] * h + low[k][1] * l;
  }
  fftwf_execute_dft_c2r(top.inverse, band, ws.real);
  return std::vector<float>(ws.real, ws.real + top.real_size());
}

}  // namespace mesocap
