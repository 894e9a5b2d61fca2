#include "reconstruct/ptm.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <numbers>
#include <type_traits>

#include "core/directions.h"
#include "core/parallel.h"
#include "core/simd.h"
#include "core/text_format.h"

namespace mesocap {

std::string PtmFormatToString(PtmFormat format) {
  switch (format) {
    case PtmFormat::kLrgb:
      return "lrgb";
    case PtmFormat::kRgb:
      return "rgb";
  }
  return "unknown";
}

bool StringToPtmFormat(const std::string& name, PtmFormat* format) {
  std::string lower = name;
  for (char& c : lower) c = char(std::tolower(static_cast<unsigned char>(c)));
  if (lower == "lrgb")
    *format = PtmFormat::kLrgb;
  else if (lower == "rgb")
    *format = PtmFormat::kRgb;
  else
    return false;
  return true;
}

bool Ptm::IsConsistent() const {
  if (coefficients.empty()) return false;
  if (format == PtmFormat::kLrgb) {
    return coefficients.channels() == kPtmCoefficients && rgb.channels() == 3 &&
           rgb.width() == coefficients.width() && rgb.height() == coefficients.height();
  }
  return coefficients.channels() == 3 * kPtmCoefficients && rgb.empty();
}

bool PtmFitOptions::Check() const {
  return near_duplicate_light_deg >= 0 && near_duplicate_light_deg < 90 && warn_condition >= 1 &&
         max_condition >= warn_condition && black_level >= 0 &&
         (num_threads == -1 || num_threads >= 1);
}

std::string PtmFitReport::Brief() const {
  char residual[64] = "not computed";
  if (rms_residual >= 0) std::snprintf(residual, sizeof residual, "%.5f", rms_residual);
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "PTM fit: %dx%d px, %d lights, light-matrix condition %.3g, rms residual %s, "
                "%.3f s",
                width, height, num_lights, light_matrix_condition, residual, fit_seconds);
  return buf;
}

Eigen::Matrix<double, 1, 6> PtmBasis(const Eigen::Vector3d& light_dir) {
  const Eigen::Vector3d d = light_dir.normalized();
  const double u = d.x(), v = d.y();
  Eigen::Matrix<double, 1, 6> b;
  b << u * u, v * v, u * v, u, v, 1.0;
  return b;
}

namespace {

std::string VecText(const Eigen::Vector3d& d) {
  char buf[128];
  std::snprintf(buf, sizeof buf, "(%g, %g, %g)", d.x(), d.y(), d.z());
  return buf;
}

Eigen::MatrixXd LightMatrix(const std::vector<Eigen::Vector3d>& light_dirs) {
  Eigen::MatrixXd a(light_dirs.size(), kPtmCoefficients);
  for (size_t i = 0; i < light_dirs.size(); ++i) a.row(i) = PtmBasis(light_dirs[i]);
  return a;
}

inline double EvalPoly(const double a[6], double u, double v) {
  return a[0] * u * u + a[1] * v * v + a[2] * u * v + a[3] * u + a[4] * v + a[5];
}

}  // namespace

namespace {

// Where the light set leaves the hemisphere empty, for the message that refuses it: the span of
// elevations and the largest gap in azimuth (degrees).
std::string MissingLightDirections(const std::vector<Eigen::Vector3d>& light_dirs) {
  double lowest = 90, highest = -90;
  std::vector<double> azimuths;
  for (const Eigen::Vector3d& d : light_dirs) {
    const Eigen::Vector3d n = d.normalized();
    const double elevation = std::asin(std::clamp(n.z(), -1.0, 1.0)) * 180 / std::numbers::pi;
    lowest = std::min(lowest, elevation), highest = std::max(highest, elevation);
    if (std::hypot(n.x(), n.y()) > 1e-6) azimuths.push_back(std::atan2(n.y(), n.x()) * 180 / std::numbers::pi);
  }
  std::sort(azimuths.begin(), azimuths.end());
  double gap = 360, gap_from = 0;
  for (size_t i = 0; i < azimuths.size(); ++i) {
    const double next = i + 1 < azimuths.size() ? azimuths[i + 1] : azimuths[0] + 360;
    if (i == 0 || next - azimuths[i] > gap) gap = next - azimuths[i], gap_from = azimuths[i];
  }
  std::string hint;
  if (highest - lowest < 15)
    hint = Format("all lights lie at elevations %.1f to %.1f deg: add lights at other elevations "
                  "(above %.0f or below %.0f deg)", lowest, highest, std::min(highest + 15, 85.0),
                  std::max(lowest - 15, 5.0));
  if (!azimuths.empty() && gap > 120) {
    if (!hint.empty()) hint += "; ";
    const auto wrap = [](double a) { return std::fmod(a + 720, 360); };
    hint += Format("no light between azimuths %.0f and %.0f deg: add lights there", wrap(gap_from),
                   wrap(gap_from + gap));
  }
  if (hint.empty()) hint = "add lights at other elevations and azimuths";
  return hint;
}

// The light matrix with each column scaled to unit length: its condition number no longer
// depends on the units of the basis (lu^2 is small near the zenith, 1 is not).
Eigen::MatrixXd NormalisedLightMatrix(const std::vector<Eigen::Vector3d>& light_dirs) {
  Eigen::MatrixXd a = LightMatrix(light_dirs);
  for (int k = 0; k < a.cols(); ++k)
    if (const double norm = a.col(k).norm(); norm > 0) a.col(k) /= norm;
  return a;
}

}  // namespace

Status ValidatePtmLights(const std::vector<Eigen::Vector3d>& light_dirs,
                         const PtmFitOptions& options, PtmLightCheck* check) {
  const int n = int(light_dirs.size());
  if (n < kPtmCoefficients)
    return Status::Error(
        "a PTM fit needs at least 6 light directions (6 coefficients per pixel), got " +
        std::to_string(n));
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d& d = light_dirs[i];
    if (!d.allFinite() || d.norm() < 1e-12)
      return Status::Error("light " + std::to_string(i + 1) + " of " + std::to_string(n) +
                           ": direction " + VecText(d) + " is not a valid direction");
  }
  // Collinear in the (lu, lv) plane: the affine part [lu, lv, 1] already loses rank.
  Eigen::MatrixXd affine(n, 3);
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d d = light_dirs[i].normalized();
    affine.row(i) << d.x(), d.y(), 1.0;
  }
  const Eigen::VectorXd sa = Eigen::JacobiSVD<Eigen::MatrixXd>(affine).singularValues();
  if (sa(2) < 1e-9 * sa(0))
    return Status::Error(
        "all " + std::to_string(n) +
        " light directions are collinear in the (lu, lv) plane (e.g. all in one "
        "vertical plane): a biquadratic PTM cannot be fitted; add lights off that line");
  const Eigen::VectorXd s = Eigen::JacobiSVD<Eigen::MatrixXd>(NormalisedLightMatrix(light_dirs)).singularValues();
  const double condition = s(0) / s(s.size() - 1);
  if (!(condition <= options.max_condition)) {
    int rank = 0;
    for (int k = 0; k < s.size(); ++k) rank += s(k) > 1e-9 * s(0);
    return Status::Error(Format(
        "the %d light directions are too poorly spread for a biquadratic PTM: the light matrix "
        "[lu^2, lv^2, lu*lv, lu, lv, 1] has condition number %.3g (limit %.3g, numerical rank %d "
        "of 6), so the fit would amplify photo noise into the coefficients; %s",
        n, condition, options.max_condition, rank, MissingLightDirections(light_dirs).c_str()));
  }
  if (!check) return Status::Ok();
  check->condition = condition;
  check->warnings.clear();
  if (condition > options.warn_condition)
    check->warnings.push_back(Format(
        "the light matrix has condition number %.3g (above %.3g): expect noisy coefficients; %s",
        condition, options.warn_condition, MissingLightDirections(light_dirs).c_str()));
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j)
      if (const double angle = AngleBetweenDeg(light_dirs[i], light_dirs[j]);
          angle < options.near_duplicate_light_deg)
        check->warnings.push_back(Format(
            "lights %d and %d of %d are %.3g deg apart (a repeated shot?): both are used",
            i + 1, j + 1, n, angle));
  return Status::Ok();
}

namespace {

// The fit runs over one block of one row at a time: the observations of a block for all lights
// (n x 3 x kBlockPixels floats, 27 KB for 36 lights) stay in cache, the inputs are read once and
// converted to float only there, so 8-bit inputs never exist as float images.
constexpr int kBlockPixels = 64;
// Values per register-blocked chunk of the multiply-add kernels: 6 accumulators of kLane
// floats each (GCC/Clang vector extension: two SSE registers each on baseline x86-64, one with
// AVX), so the loops over lights run from registers.
constexpr int kLane = 8;
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"  // Lane is passed only between inlined helpers
typedef float Lane __attribute__((vector_size(kLane * sizeof(float))));

// By reference, never by value: a Lane returned from a baseline helper into an x86-64-v3 clone
// would change the ABI (clang refuses it; gcc warns).
inline void LoadLane(const float* p, Lane& v) { std::memcpy(&v, p, sizeof v); }
inline void StoreLane(float* p, const Lane& v) { std::memcpy(p, &v, sizeof v); }

// The kernels are also compiled for AVX2 + FMA (core/simd.h): 8-wide fused multiply-adds instead
// of 4-wide multiplies and adds on baseline x86-64.

int RoundUpToLane(int len) { return (len + kLane - 1) / kLane * kLane; }

// Helpers of the cloned kernels are always inlined: each clone then compiles them for its own
// target. Called instead, the x86-64-v3 clone ran their baseline code (fit-ptm's fit 10x
// slower, without fused multiply-adds).
#define MESOCAP_KERNEL_HELPER __attribute__((always_inline)) inline

// SolveBlock for kChunks chunks of kLane values from j0: each broadcast p[k * n + i] serves every
// chunk (with one chunk the loop is bound by loads, not by multiply-adds).
template <int kChunks>
MESOCAP_KERNEL_HELPER void SolveChunks(const float* obs, int n, int stride, const float* p, int j0, float* out) {
  Lane acc[kChunks][kPtmCoefficients] = {};
  for (int i = 0; i < n; ++i) {
    Lane v[kChunks];
    for (int h = 0; h < kChunks; ++h) LoadLane(obs + size_t(i) * stride + j0 + h * kLane, v[h]);
    for (int k = 0; k < kPtmCoefficients; ++k) {
      const float pk = p[k * n + i];
      for (int h = 0; h < kChunks; ++h) acc[h][k] += pk * v[h];
    }
  }
  for (int k = 0; k < kPtmCoefficients; ++k)
    for (int h = 0; h < kChunks; ++h) StoreLane(out + size_t(k) * stride + j0 + h * kLane, acc[h][k]);
}

// out[k * stride + j] = sum_i p[k * n + i] * obs[i * stride + j] for j < stride (a multiple of
// kLane): the least-squares coefficients of every value, with p = pinv(A) row-major 6 x n. The
// sum runs over the lights in order, so the result does not depend on blocks or threads. Two
// chunks of kLane values at a time, then the odd one.
MESOCAP_SIMD_CLONES void SolveBlock(const float* obs, int n, int stride, const float* p, float* out) {
  int j0 = 0;
  for (; j0 + 2 * kLane <= stride; j0 += 2 * kLane) SolveChunks<2>(obs, n, stride, p, j0, out);
  for (; j0 < stride; j0 += kLane) SolveChunks<1>(obs, n, stride, p, j0, out);
}

// dst[j * 6 + k] = src[k * stride + j] for j < len: a block's coefficients, solved as one run
// per coefficient index, into the Ptm's six per value. Four values at a time: a 4x4 transpose of
// coefficients 0-3 and the pairs of 4 and 5, woven by shuffles.
typedef float Quad __attribute__((vector_size(4 * sizeof(float))));
MESOCAP_SIMD_CLONES void InterleaveCoefficients(const float* src, int stride, int len, float* dst) {
  int j = 0;
  for (; j + 4 <= len; j += 4) {
    Quad r[kPtmCoefficients];
    for (int k = 0; k < kPtmCoefficients; ++k) std::memcpy(&r[k], src + size_t(k) * stride + j, sizeof r[k]);
    const Quad a = __builtin_shufflevector(r[0], r[1], 0, 4, 1, 5), b = __builtin_shufflevector(r[2], r[3], 0, 4, 1, 5);
    const Quad c = __builtin_shufflevector(r[0], r[1], 2, 6, 3, 7), d = __builtin_shufflevector(r[2], r[3], 2, 6, 3, 7);
    const Quad t[4] = {__builtin_shufflevector(a, b, 0, 1, 4, 5), __builtin_shufflevector(a, b, 2, 3, 6, 7),
                       __builtin_shufflevector(c, d, 0, 1, 4, 5), __builtin_shufflevector(c, d, 2, 3, 6, 7)};
    const Quad u = __builtin_shufflevector(r[4], r[5], 0, 4, 1, 5), v = __builtin_shufflevector(r[4], r[5], 2, 6, 3, 7);
    const Quad out[6] = {t[0],
                         __builtin_shufflevector(u, t[1], 0, 1, 4, 5),
                         __builtin_shufflevector(t[1], u, 2, 3, 6, 7),
                         t[2],
                         __builtin_shufflevector(v, t[3], 0, 1, 4, 5),
                         __builtin_shufflevector(t[3], v, 2, 3, 6, 7)};
    std::memcpy(dst + size_t(j) * kPtmCoefficients, out, sizeof out);
  }
  for (; j < len; ++j)
    for (int k = 0; k < kPtmCoefficients; ++k) dst[size_t(j) * kPtmCoefficients + k] = src[size_t(k) * stride + j];
}

// dst[j] = float(src[j]) * scale for j < len: a block's observations as float. One clone pair
// per input type (clang's target_clones does not take templates).
template <typename T>
MESOCAP_KERNEL_HELPER void ConvertEach(const T* src, int len, float scale, float* dst) {
  for (int j = 0; j < len; ++j) dst[j] = float(src[j]) * scale;
}
MESOCAP_SIMD_CLONES void ConvertValues(const uint8_t* src, int len, float scale, float* dst) {
  ConvertEach(src, len, scale, dst);
}
MESOCAP_SIMD_CLONES void ConvertValues(const float* src, int len, float scale, float* dst) {
  ConvertEach(src, len, scale, dst);
}

// fitted[j] = sum_k a_row[k] * coef[k * stride + j]: the fit evaluated at one light.
MESOCAP_SIMD_CLONES void EvaluateBlock(const float* coef, const float* a_row, int stride, float* fitted) {
  for (int j0 = 0; j0 < stride; j0 += kLane) {
    Lane f = {};
    for (int k = 0; k < kPtmCoefficients; ++k) {
      Lane c;
      LoadLane(coef + size_t(k) * stride + j0, c);
      f += a_row[k] * c;
    }
    StoreLane(fitted + j0, f);
  }
}

// ResidualBlock for kChunks chunks of kLane values from j0, as SolveChunks; the chunks' sums are
// added to *total in order.
template <int kChunks>
MESOCAP_KERNEL_HELPER void ResidualChunks(const float* obs, int n, int stride, const float* a, const float* coef, int j0,
                                           double* total) {
  Lane c[kChunks][kPtmCoefficients];
  for (int k = 0; k < kPtmCoefficients; ++k)
    for (int h = 0; h < kChunks; ++h) LoadLane(coef + size_t(k) * stride + j0 + h * kLane, c[h][k]);
  Lane s[kChunks] = {};
  for (int i = 0; i < n; ++i) {
    const float* ai = a + i * kPtmCoefficients;
    Lane f[kChunks] = {};
    for (int k = 0; k < kPtmCoefficients; ++k)
      for (int h = 0; h < kChunks; ++h) f[h] += ai[k] * c[h][k];
    for (int h = 0; h < kChunks; ++h) {
      Lane o;
      LoadLane(obs + size_t(i) * stride + j0 + h * kLane, o);
      const Lane r = f[h] - o;
      s[h] += r * r;
    }
  }
  for (int h = 0; h < kChunks; ++h)
    for (int l = 0; l < kLane; ++l) *total += s[h][l];
}

// Sum over lights and values of (fit - observation)^2, with a row-major n x 6: two chunks at a
// time, then the odd one.
MESOCAP_SIMD_CLONES double ResidualBlock(const float* obs, int n, int stride, const float* a, const float* coef) {
  double total = 0;
  int j0 = 0;
  for (; j0 + 2 * kLane <= stride; j0 += 2 * kLane) ResidualChunks<2>(obs, n, stride, a, coef, j0, &total);
  for (; j0 < stride; j0 += kLane) ResidualChunks<1>(obs, n, stride, a, coef, j0, &total);
  return total;
}

#pragma GCC diagnostic pop

// Size and channel checks shared by the float and 8-bit entry points.
template <typename ImageT>
Status CheckPtmImages(const std::vector<ImageT>& images) {
  const int n = int(images.size());
  const int width = images[0].width(), height = images[0].height(),
            channels = images[0].channels();
  if (images[0].empty()) return Status::Error("PTM fit: image 1 is empty");
  if (channels != 1 && channels != 3 && channels != 4)
    return Status::Error("PTM fit: images must have 1, 3 or 4 channels, image 1 has " +
                         std::to_string(channels));
  for (int i = 1; i < n; ++i) {
    const ImageT& im = images[i];
    if (im.width() != width || im.height() != height || im.channels() != channels) {
      return Status::Error(
          "PTM fit: image " + std::to_string(i + 1) + " is " + std::to_string(im.width()) + "x" +
          std::to_string(im.height()) + "x" + std::to_string(im.channels()) + " but image 1 is " +
          std::to_string(width) + "x" + std::to_string(height) + "x" + std::to_string(channels) +
          ": all images must have the same size and channel count");
    }
  }
  return Status::Ok();
}

}  // namespace

// The fit of one row: rows[i] is row y of image i, width * channels values of T, each counted
// as value * scale.
template <typename T>
void PtmRowFitter::FitRow(int y, const T* const* rows, float scale, float* coef_row, float* rgb_row) {
  const int n = n_, width = width_, channels = channels_;
  const bool lrgb = options_.format == PtmFormat::kLrgb;
  // Scratch buffers live per thread: allocating them per row costs more than the fit.
  thread_local std::vector<float> obs, coef, lum, fitted, ymax, inv;
  thread_local std::vector<double> num, den;
  double sse = 0;
  for (int x0 = 0; x0 < width; x0 += kBlockPixels) {
    const int bw = std::min(kBlockPixels, width - x0);
    // The block's observations as float, 3 interleaved values per pixel (grey replicated,
    // alpha dropped), one zero-padded run of `stride` values per light.
    const int len = 3 * bw, stride = RoundUpToLane(len);
    obs.resize(size_t(n) * stride);
    for (int i = 0; i < n; ++i) {
      const T* src = rows[i] + size_t(x0) * channels;
      float* dst = obs.data() + size_t(i) * stride;
      // The inputs are n separate streams, too many for the hardware prefetcher: ask for
      // the next block of this image while converting this one.
      if (x0 + kBlockPixels < width) {
        const char* next = reinterpret_cast<const char*>(src + size_t(bw) * channels);
        const size_t bytes = size_t(std::min(kBlockPixels, width - x0 - kBlockPixels)) *
                             channels * sizeof(T);
        for (size_t b = 0; b < bytes; b += 64) __builtin_prefetch(next + b);
      }
      if (channels == 3) {
        ConvertValues(src, len, scale, dst);
      } else {
        for (int x = 0; x < bw; ++x)
          for (int c = 0; c < 3; ++c)
            dst[x * 3 + c] = float(src[size_t(x) * channels + (channels == 1 ? 0 : c)]) * scale;
      }
      for (int j = len; j < stride; ++j) dst[j] = 0.0f;
    }
    if (!lrgb) {
      coef.resize(size_t(kPtmCoefficients) * stride);
      SolveBlock(obs.data(), n, stride, p_.data(), coef.data());
      // Value j = 3 x + c of the block is pixel x0 + x's channel c: its six coefficients sit at
      // (x0 + x) * 18 + c * 6 = x0 * 18 + j * 6.
      InterleaveCoefficients(coef.data(), stride, len, coef_row + size_t(x0) * 18);
      if (options_.compute_residual)
        sse += ResidualBlock(obs.data(), n, stride, a_f_.data(), coef.data());
      continue;
    }
    // LRGB: luminance per light, normalised per pixel by its brightest observation.
    const int lstride = RoundUpToLane(bw);
    lum.assign(size_t(n) * lstride, 0.0f);
    ymax.assign(lstride, 0.0f);
    inv.assign(lstride, 0.0f);
    for (int i = 0; i < n; ++i) {
      const float* o = obs.data() + size_t(i) * stride;
      float* l = lum.data() + size_t(i) * lstride;
      for (int x = 0; x < bw; ++x) {
        l[x] = kPtmLumaWeights[0] * o[x * 3] + kPtmLumaWeights[1] * o[x * 3 + 1] +
               kPtmLumaWeights[2] * o[x * 3 + 2];
        ymax[x] = std::max(ymax[x], l[x]);
      }
    }
    for (int x = 0; x < bw; ++x)
      inv[x] = ymax[x] > options_.black_level ? 1.0f / ymax[x] : 0.0f;
    for (int i = 0; i < n; ++i) {
      float* l = lum.data() + size_t(i) * lstride;
      for (int x = 0; x < bw; ++x) l[x] *= inv[x];
    }
    coef.resize(size_t(kPtmCoefficients) * lstride);
    SolveBlock(lum.data(), n, lstride, p_.data(), coef.data());
    // The colour that best matches the observations given the fitted luminance:
    // rgb_c = sum_i L_i obs_ic / sum_i L_i^2.
    num.assign(size_t(bw) * 3, 0.0);
    den.assign(bw, 0.0);
    fitted.resize(lstride);
    for (int i = 0; i < n; ++i) {
      EvaluateBlock(coef.data(), a_f_.data() + i * kPtmCoefficients, lstride, fitted.data());
      const float* o = obs.data() + size_t(i) * stride;
      for (int x = 0; x < bw; ++x) {
        const double f = fitted[x];
        den[x] += f * f;
        for (int c = 0; c < 3; ++c) num[x * 3 + c] += f * o[x * 3 + c];
      }
    }
    for (int x = 0; x < bw; ++x) {
      float rgb[3] = {0, 0, 0};
      float gain = 0;  // the factor applied to the fitted polynomial
      if (inv[x] > 0 && den[x] > 1e-20) {
        for (int c = 0; c < 3; ++c) rgb[c] = float(std::max(0.0, num[x * 3 + c] / den[x]));
        // Keep the colour representable in 8 bits: move any excess into the polynomial.
        const float peak = std::max({rgb[0], rgb[1], rgb[2]});
        gain = 1.0f;
        if (peak > 1.0f) {
          for (float& v : rgb) v /= peak;
          gain = peak;
        }
      }
      for (int k = 0; k < kPtmCoefficients; ++k) {
        float& ck = coef[size_t(k) * lstride + x];
        ck *= gain;
        coef_row[size_t(x0 + x) * 6 + k] = ck;
      }
      for (int c = 0; c < 3; ++c) rgb_row[size_t(x0 + x) * 3 + c] = rgb[c];
    }
    for (int i = 0; i < n && options_.compute_residual; ++i) {
      EvaluateBlock(coef.data(), a_f_.data() + i * kPtmCoefficients, lstride, fitted.data());
      const float* o = obs.data() + size_t(i) * stride;
      const float* rgb = rgb_row + size_t(x0) * 3;
      float light_sse = 0;
      for (int x = 0; x < bw; ++x)
        for (int c = 0; c < 3; ++c) {
          const float r = fitted[x] * rgb[x * 3 + c] - o[x * 3 + c];
          light_sse += r * r;
        }
      sse += light_sse;
    }
  }
  row_sse_[size_t(y)] = sse;
}

StatusOr<PtmRowFitter> PtmRowFitter::Create(const std::vector<Eigen::Vector3d>& light_dirs, int width, int height,
                                            int channels, const PtmFitOptions& options) {
  MESOCAP_CHECK(options.Check(), "invalid PtmFitOptions");
  PtmLightCheck light_check;
  MESOCAP_RETURN_IF_ERROR(ValidatePtmLights(light_dirs, options, &light_check));
  if (width <= 0 || height <= 0) return Status::Error("PTM fit: the images are empty");
  if (channels != 1 && channels != 3 && channels != 4)
    return Status::Error("PTM fit: images must have 1, 3 or 4 channels, not " + std::to_string(channels));
  PtmRowFitter fitter;
  fitter.start_ = std::chrono::steady_clock::now();
  fitter.options_ = options;
  fitter.light_check_ = std::move(light_check);
  fitter.n_ = int(light_dirs.size());
  fitter.width_ = width;
  fitter.height_ = height;
  fitter.channels_ = channels;
  // One shared solve: the pseudo-inverse of the light matrix maps observations to coefficients.
  const int n = fitter.n_;
  const Eigen::MatrixXd a = LightMatrix(light_dirs);
  const Eigen::MatrixXd pinv = a.colPivHouseholderQr().solve(Eigen::MatrixXd::Identity(n, n));  // 6 x n
  fitter.p_.resize(size_t(kPtmCoefficients) * n);
  fitter.a_f_.resize(size_t(n) * kPtmCoefficients);
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < kPtmCoefficients; ++k) {
      fitter.p_[k * n + i] = float(pinv(k, i));
      fitter.a_f_[i * kPtmCoefficients + k] = float(a(i, k));
    }
  fitter.row_sse_.assign(size_t(height), 0.0);
  return fitter;
}

Ptm PtmRowFitter::NewRows(int rows) const {
  MESOCAP_CHECK(rows > 0, "PtmRowFitter::NewRows: no rows");
  Ptm ptm;
  ptm.format = options_.format;
  const bool lrgb = options_.format == PtmFormat::kLrgb;
  ptm.coefficients = Image::Uninitialized(width_, rows, lrgb ? kPtmCoefficients : 3 * kPtmCoefficients);
  if (lrgb) ptm.rgb = Image::Uninitialized(width_, rows, 3);
  return ptm;
}

template <typename T>
void PtmRowFitter::FitRowsOf(int y0, int y1, const std::function<const T*(int, int)>& row, float scale, Ptm* into,
                             const std::function<void(int)>& fitted) {
  MESOCAP_CHECK(0 <= y0 && y0 <= y1 && y1 <= height_, "PtmRowFitter: rows out of range");
  MESOCAP_CHECK(into && into->format == options_.format && into->width() == width_ && into->height() >= y1 - y0,
                "PtmRowFitter: the target Ptm does not fit the rows");
  ParallelFor(
      y0, y1,
      [&](int y) {
        FitRowOf(y, y0, row, scale, into);
        if (fitted) fitted(y);
      },
      options_.num_threads);
}

template <typename T>
void PtmRowFitter::FitRowOf(int y, int y0, const std::function<const T*(int, int)>& row, float scale, Ptm* into) {
  thread_local std::vector<const T*> rows;
  rows.resize(size_t(n_));
  for (int i = 0; i < n_; ++i) rows[size_t(i)] = row(i, y);
  FitRow(y, rows.data(), scale, into->coefficients.row(y - y0), into->rgb.empty() ? nullptr : into->rgb.row(y - y0));
}

void PtmRowFitter::FitRow(int y, int y0, const std::function<const uint8_t*(int, int)>& row, Ptm* into) {
  MESOCAP_CHECK(0 <= y0 && y0 <= y && y < height_, "PtmRowFitter: row out of range");
  MESOCAP_CHECK(into && into->format == options_.format && into->width() == width_ && into->height() > y - y0,
                "PtmRowFitter: the target Ptm does not fit the row");
  FitRowOf<uint8_t>(y, y0, row, kU8ToUnit, into);
}

void PtmRowFitter::FitRows(int y0, int y1, const std::function<const float*(int, int)>& row, Ptm* into,
                           const std::function<void(int)>& fitted) {
  FitRowsOf<float>(y0, y1, row, 1.0f, into, fitted);
}

void PtmRowFitter::FitRows(int y0, int y1, const std::function<const uint8_t*(int, int)>& row, Ptm* into,
                           const std::function<void(int)>& fitted) {
  FitRowsOf<uint8_t>(y0, y1, row, kU8ToUnit, into, fitted);
}

void PtmRowFitter::Report(PtmFitReport* report) const {
  double sse = 0;
  for (double v : row_sse_) sse += v;  // in row order: independent of the thread count
  report->num_lights = n_;
  report->width = width_;
  report->height = height_;
  report->light_matrix_condition = light_check_.condition;
  report->warnings = light_check_.warnings;
  report->rms_residual = options_.compute_residual ? std::sqrt(sse / (double(width_) * height_ * n_ * 3)) : -1.0;
  report->fit_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

namespace {

// The fit of whole images of one type: FitPtm's two overloads.
template <typename ImageT>
StatusOr<Ptm> FitWholeImages(const std::vector<ImageT>& images, const std::vector<Eigen::Vector3d>& light_dirs,
                             const PtmFitOptions& options, PtmFitReport* report) {
  using T = std::remove_cv_t<std::remove_pointer_t<decltype(images[0].data())>>;
  if (images.size() != light_dirs.size())
    return Status::Error("PTM fit: " + std::to_string(images.size()) + " images but " +
                         std::to_string(light_dirs.size()) + " light directions; they must pair up");
  MESOCAP_RETURN_IF_ERROR(ValidatePtmLights(light_dirs, options));
  MESOCAP_RETURN_IF_ERROR(CheckPtmImages(images));
  auto fitter = PtmRowFitter::Create(light_dirs, images[0].width(), images[0].height(), images[0].channels(), options);
  if (!fitter.ok()) return fitter.status();
  const std::function<const T*(int, int)> row = [&](int i, int y) -> const T* { return images[size_t(i)].row(y); };
  Ptm ptm = fitter->NewRows(images[0].height());
  fitter->FitRows(0, images[0].height(), row, &ptm);
  if (report) fitter->Report(report);
  return ptm;
}

}  // namespace

StatusOr<Ptm> FitPtm(const std::vector<Image>& images, const std::vector<Eigen::Vector3d>& light_dirs,
                     const PtmFitOptions& options, PtmFitReport* report) {
  return FitWholeImages(images, light_dirs, options, report);
}

StatusOr<Ptm> FitPtm(const std::vector<ImageU8>& images, const std::vector<Eigen::Vector3d>& light_dirs,
                     const PtmFitOptions& options, PtmFitReport* report) {
  return FitWholeImages(images, light_dirs, options, report);
}

StatusOr<Ptm> FitPtmPerPixelLights(const std::vector<Image>& images, const PixelLightFn& light_dir,
                                   const PtmFitOptions& options, PtmFitReport* report, int* degenerate_pixels,
                                   Image* residual_map) {
  MESOCAP_CHECK(options.Check(), "invalid PtmFitOptions");
  const auto start = std::chrono::steady_clock::now();
  if (images.size() < size_t(kPtmCoefficients))
    return Status::Error("PTM fit: " + std::to_string(images.size()) + " images; at least 6 lights are needed");
  MESOCAP_RETURN_IF_ERROR(CheckPtmImages(images));
  const int n = int(images.size());
  const int width = images[0].width(), height = images[0].height(), channels = images[0].channels();
  const bool lrgb = options.format == PtmFormat::kLrgb;
  Ptm ptm;
  ptm.format = options.format;
  ptm.coefficients = Image(width, height, lrgb ? kPtmCoefficients : 3 * kPtmCoefficients);
  if (lrgb) ptm.rgb = Image(width, height, 3);
  std::vector<double> row_sse(height, 0.0);
  std::vector<int> row_degenerate(height, 0);
  if (residual_map) *residual_map = Image(width, height, 1);
  const auto record = [&](int x, int y, double pixel_sse) {
    row_sse[y] += pixel_sse;
    if (residual_map) residual_map->at(x, y, 0) = float(std::sqrt(pixel_sse / (3.0 * n)));
  };
  ParallelFor(0, height, [&](int y) {
    Eigen::MatrixXd a(n, kPtmCoefficients), obs(n, 3);
    for (int x = 0; x < width; ++x) {
      for (int i = 0; i < n; ++i) {
        a.row(i) = PtmBasis(light_dir(i, x, y));
        const float* px = images[i].pixel(x, y);
        for (int c = 0; c < 3; ++c) obs(i, c) = px[channels == 1 ? 0 : c];
      }
      const Eigen::Matrix<double, 6, 6> ata = a.transpose() * a;
      const Eigen::LDLT<Eigen::Matrix<double, 6, 6>> ldlt(ata);
      const double scale = ata.diagonal().maxCoeff();
      if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().cwiseAbs().minCoeff() > 1e-12 * scale)) {
        ++row_degenerate[y];
        continue;
      }
      float* coef = ptm.coefficients.pixel(x, y);
      if (!lrgb) {
        const Eigen::Matrix<double, 6, 3> c = ldlt.solve(a.transpose() * obs);
        for (int ch = 0; ch < 3; ++ch)
          for (int k = 0; k < kPtmCoefficients; ++k) coef[ch * 6 + k] = float(c(k, ch));
        record(x, y, (a * c - obs).squaredNorm());
        continue;
      }
      // LRGB as in the shared fit: luminance normalised by its brightest observation, then the
      // colour that best matches the observations given the fitted luminance.
      Eigen::VectorXd lum = obs * Eigen::Vector3d(kPtmLumaWeights[0], kPtmLumaWeights[1], kPtmLumaWeights[2]);
      const double ymax = lum.maxCoeff();
      if (!(ymax > options.black_level)) continue;
      lum /= ymax;
      Eigen::Matrix<double, 6, 1> c = ldlt.solve(a.transpose() * lum);
      const Eigen::VectorXd fitted = a * c;
      const double den = fitted.squaredNorm();
      Eigen::Vector3d rgb = den > 1e-20 ? Eigen::Vector3d((obs.transpose() * fitted / den).cwiseMax(0.0)) : Eigen::Vector3d::Zero();
      const double peak = rgb.maxCoeff();
      if (peak > 1.0) rgb /= peak, c *= peak;  // keep the colour representable in 8 bits
      for (int k = 0; k < kPtmCoefficients; ++k) coef[k] = float(c(k));
      float* out_rgb = ptm.rgb.pixel(x, y);
      for (int ch = 0; ch < 3; ++ch) out_rgb[ch] = float(rgb(ch));
      record(x, y, ((a * c) * rgb.transpose() - obs).squaredNorm());
    }
  }, options.num_threads);
  double sse = 0;
  int degenerate = 0;
  for (int y = 0; y < height; ++y) sse += row_sse[y], degenerate += row_degenerate[y];
  if (degenerate_pixels) *degenerate_pixels = degenerate;
  if (report) {
    report->num_lights = n;
    report->width = width;
    report->height = height;
    report->rms_residual = std::sqrt(sse / (double(width) * height * n * 3));
    report->fit_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  return ptm;
}

PixelLightFn PointLightDirections(std::vector<Eigen::Vector3d> lights_m, int size, double patch_m) {
  return [lights = std::move(lights_m), size, patch_m](int i, int x, int y) {
    const Eigen::Vector3d texel(-patch_m / 2 + (x + 0.5) * patch_m / size, patch_m / 2 - (y + 0.5) * patch_m / size, 0.0);
    return Eigen::Vector3d((lights[i] - texel).normalized());
  };
}

Image RelightPtm(const Ptm& ptm, const Eigen::Vector3d& light_dir, bool clamp, int num_threads) {
  MESOCAP_CHECK(ptm.IsConsistent(), "inconsistent Ptm");
  MESOCAP_CHECK(light_dir.allFinite() && light_dir.norm() > 0, "invalid light direction");
  const Eigen::Matrix<double, 1, 6> bd = PtmBasis(light_dir);
  float b[6];
  for (int k = 0; k < 6; ++k) b[k] = float(bd(k));
  const int width = ptm.width();
  Image out(width, ptm.height(), 3);
  const bool lrgb = ptm.format == PtmFormat::kLrgb;
  ParallelFor(
      0, ptm.height(),
      [&](int y) {
        const float* coef = ptm.coefficients.row(y);
        float* dst = out.row(y);
        for (int x = 0; x < width; ++x) {
          float value[3];
          if (lrgb) {
            const float* a = coef + size_t(x) * 6;
            const float l =
                b[0] * a[0] + b[1] * a[1] + b[2] * a[2] + b[3] * a[3] + b[4] * a[4] + b[5] * a[5];
            const float* rgb = ptm.rgb.pixel(x, y);
            for (int c = 0; c < 3; ++c) value[c] = l * rgb[c];
          } else {
            for (int c = 0; c < 3; ++c) {
              const float* a = coef + size_t(x) * 18 + c * 6;
              value[c] =
                  b[0] * a[0] + b[1] * a[1] + b[2] * a[2] + b[3] * a[3] + b[4] * a[4] + b[5] * a[5];
            }
          }
          for (int c = 0; c < 3; ++c)
            dst[x * 3 + c] = clamp ? (value[c] > 0.0f ? std::min(value[c], 1.0f) : 0.0f) : value[c];
        }
      },
      num_threads);
  return out;
}

Eigen::Vector3d PtmMaximumDirection(const double a[6]) {
  double scale = 0;
  for (int k = 0; k < 5; ++k) scale = std::max(scale, std::abs(a[k]));
  if (!(scale > 1e-12 * std::max(1.0, std::abs(a[5]))))
    return {0, 0, 1};  // flat: no preferred direction
  // Interior maximum where the quadratic is concave (Hessian [[2a0, a2], [a2, 2a1]] negative
  // definite) and its stationary point lies inside the unit disk.
  const double det = 4 * a[0] * a[1] - a[2] * a[2];
  if (a[0] < 0 && det > 1e-12 * scale * scale) {
    const double u = (a[2] * a[4] - 2 * a[1] * a[3]) / det;
    const double v = (a[2] * a[3] - 2 * a[0] * a[4]) / det;
    if (u * u + v * v <= 1.0) return {u, v, std::sqrt(std::max(0.0, 1.0 - u * u - v * v))};
  }
  // Otherwise the maximum over the closed disk is on its boundary, the circle u^2 + v^2 = 1:
  // coarse sampling, then golden-section refinement around the best sample.
  constexpr int kSamples = 360;
  const double step = 2 * std::numbers::pi / kSamples;
  int best = 0;
  double best_value = -1e300;
  for (int s = 0; s < kSamples; ++s) {
    const double t = s * step;
    const double f = EvalPoly(a, std::cos(t), std::sin(t));
    if (f > best_value) best_value = f, best = s;
  }
  double lo = (best - 1) * step, hi = (best + 1) * step;
  const double g = (std::sqrt(5.0) - 1) / 2;
  for (int it = 0; it < 60; ++it) {
    const double t1 = hi - g * (hi - lo), t2 = lo + g * (hi - lo);
    if (EvalPoly(a, std::cos(t1), std::sin(t1)) >= EvalPoly(a, std::cos(t2), std::sin(t2)))
      hi = t2;
    else
      lo = t1;
  }
  const double t = 0.5 * (lo + hi);
  return {std::cos(t), std::sin(t), 0.0};
}

PtmNormalsAlbedo PtmNormalsAndAlbedo(const Ptm& ptm, int num_threads) {
  MESOCAP_CHECK(ptm.IsConsistent(), "inconsistent Ptm");
  const int width = ptm.width();
  PtmNormalsAlbedo out{Image(width, ptm.height(), 3), Image(width, ptm.height(), 3)};
  const bool lrgb = ptm.format == PtmFormat::kLrgb;
  ParallelFor(
      0, ptm.height(),
      [&](int y) {
        for (int x = 0; x < width; ++x) {
          const float* coef = ptm.coefficients.pixel(x, y);
          double lum[6];
          if (lrgb) {
            for (int k = 0; k < 6; ++k) lum[k] = coef[k];
          } else {
            for (int k = 0; k < 6; ++k)
              lum[k] = kPtmLumaWeights[0] * coef[k] + kPtmLumaWeights[1] * coef[6 + k] +
                       kPtmLumaWeights[2] * coef[12 + k];
          }
          const Eigen::Vector3d n = PtmMaximumDirection(lum);
          float* normal = out.normals.pixel(x, y);
          for (int c = 0; c < 3; ++c) normal[c] = float(n(c));
          float* albedo = out.albedo.pixel(x, y);
          if (lrgb) {
            const double l = EvalPoly(lum, n.x(), n.y());
            const float* rgb = ptm.rgb.pixel(x, y);
            for (int c = 0; c < 3; ++c) albedo[c] = float(std::max(0.0, l * rgb[c]));
          } else {
            for (int c = 0; c < 3; ++c) {
              double a[6];
              for (int k = 0; k < 6; ++k) a[k] = coef[c * 6 + k];
              albedo[c] = float(std::max(0.0, EvalPoly(a, n.x(), n.y())));
            }
          }
        }
      },
      num_threads);
  return out;
}

}  // namespace mesocap
