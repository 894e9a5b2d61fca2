#include "formats/ptm_quantize.h"

#include <emmintrin.h>

#include <algorithm>
#include <cstring>
#include <limits>

#include "core/simd.h"

// Built with -ffp-contract=off (export/CMakeLists.txt): each product and sum rounds as written,
// in every clone, as the scalar code does.

namespace mesocap {
namespace {

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"  // vectors are passed only between inlined helpers
typedef float F8 __attribute__((vector_size(32)));
typedef double D4 __attribute__((vector_size(32)));
typedef int I4 __attribute__((vector_size(16)));
typedef float F4 __attribute__((vector_size(16)));
typedef float F2 __attribute__((vector_size(8)));

// Adding then subtracting 1.5 * 2^52 rounds a double of magnitude below 2^51 to an integer, half
// to even, in the default rounding mode: what cvtsd2si does, without SSE4.1's roundpd.
constexpr double kRoundingMagic = 6755399441055744.0;

// Rounds 4 doubles (file units over step, plus bias) to integers in [-1, 256], as QuantizeByte
// does before its last clamp.
inline I4 RoundedInts(const D4& value) {
  const D4 lo = {-1, -1, -1, -1}, hi = {256, 256, 256, 256}, magic = {kRoundingMagic, kRoundingMagic, kRoundingMagic, kRoundingMagic};
  D4 v = value < lo ? lo : value;
  v = v > hi ? hi : v;
  D4 r = v + magic;
  r = r - magic;
  return __builtin_convertvector(r, I4);
}

// Quantises 12 doubles to 12 bytes, as QuantizeByte does: the clamp to [0, 255] is the
// saturation of SSE2's packs (to int16) and packus (to uint8), vector instructions in place of
// four extractions and shifts per 4 bytes.
inline void StoreBytes(const D4 (&values)[3], unsigned char* dst) {
  const __m128i first = _mm_packs_epi32(__m128i(RoundedInts(values[0])), __m128i(RoundedInts(values[1])));
  const __m128i last = _mm_packs_epi32(__m128i(RoundedInts(values[2])), _mm_setzero_si128());
  const __m128i bytes = _mm_packus_epi16(first, last);
  _mm_storel_epi64(reinterpret_cast<__m128i*>(dst), bytes);
  const int tail = _mm_cvtsi128_si32(_mm_srli_si128(bytes, 8));
  std::memcpy(dst + 8, &tail, sizeof tail);
}

inline unsigned char QuantizeOne(float value, double inv_scale, int bias) {
  double v = 255.0 * double(value);
  v = v * inv_scale;
  v = v + double(bias);
  v = std::clamp(v, -1.0, 256.0);
  double r = v + kRoundingMagic;
  r = r - kRoundingMagic;
  return static_cast<unsigned char>(std::clamp(int(r), 0, 255));
}

MESOCAP_SIMD_CLONES CoefficientRange RangeKernel(const float* values, int count) {
  // Chunks of 24 values (4 pixels' 6 coefficients) in 3 vectors: lane j of vector m holds index
  // (8m + j) % 6, folded to 6 at the end.
  const float inf = std::numeric_limits<float>::infinity();
  F8 lo[3], hi[3], nan_check[3];
  for (int m = 0; m < 3; ++m) {
    for (int j = 0; j < 8; ++j) lo[m][j] = inf, hi[m][j] = -inf;
    nan_check[m] = F8{} ;
  }
  int i = 0;
  for (; i + 24 <= count; i += 24)
    for (int m = 0; m < 3; ++m) {
      F8 v;
      std::memcpy(&v, values + i + 8 * m, sizeof v);
      lo[m] = v < lo[m] ? v : lo[m];
      hi[m] = v > hi[m] ? v : hi[m];
      nan_check[m] += v - v;  // 0 for finite values, NaN for inf and NaN
    }
  CoefficientRange range;
  range.lo.fill(inf);
  range.hi.fill(-inf);
  bool finite = true;
  for (int m = 0; m < 3; ++m)
    for (int j = 0; j < 8; ++j) {
      const int k = (8 * m + j) % 6;
      range.lo[k] = std::min(range.lo[k], lo[m][j]);
      range.hi[k] = std::max(range.hi[k], hi[m][j]);
      finite = finite && nan_check[m][j] == 0.0f;
    }
  for (; i < count; ++i) {
    const float v = values[i];
    finite = finite && v - v == 0.0f;
    range.lo[i % 6] = std::min(range.lo[i % 6], v);
    range.hi[i % 6] = std::max(range.hi[i % 6], v);
  }
  range.finite = finite;
  return range;
}

MESOCAP_SIMD_CLONES void QuantizeKernel(const float* src, int stride, int pixels,
                                                               const double inv_scale[6], const int bias[6], unsigned char* dst) {
  // Two pixels (12 values) per step, in 3 vectors of 4 with the coefficient pattern k = 0..5, 0..5.
  const D4 units = {255.0, 255.0, 255.0, 255.0};
  const D4 scale[3] = {{inv_scale[0], inv_scale[1], inv_scale[2], inv_scale[3]},
                       {inv_scale[4], inv_scale[5], inv_scale[0], inv_scale[1]},
                       {inv_scale[2], inv_scale[3], inv_scale[4], inv_scale[5]}};
  const D4 offset[3] = {{double(bias[0]), double(bias[1]), double(bias[2]), double(bias[3])},
                        {double(bias[4]), double(bias[5]), double(bias[0]), double(bias[1])},
                        {double(bias[2]), double(bias[3]), double(bias[4]), double(bias[5])}};
  int x = 0;
  for (; x + 2 <= pixels; x += 2) {
    const float* a = src + size_t(x) * stride;
    const float* b = a + stride;
    F4 first, last;
    F2 a_tail, b_head;
    std::memcpy(&first, a, sizeof first);
    std::memcpy(&a_tail, a + 4, sizeof a_tail);
    std::memcpy(&b_head, b, sizeof b_head);
    std::memcpy(&last, b + 2, sizeof last);
    const F4 middle = {a_tail[0], a_tail[1], b_head[0], b_head[1]};
    const D4 values[3] = {__builtin_convertvector(first, D4), __builtin_convertvector(middle, D4),
                          __builtin_convertvector(last, D4)};
    D4 scaled[3];
    for (int m = 0; m < 3; ++m) {
      D4 v = values[m] * units;
      v = v * scale[m];
      scaled[m] = v + offset[m];
    }
    StoreBytes(scaled, dst + size_t(x) * 6);
  }
  for (; x < pixels; ++x)
    for (int k = 0; k < 6; ++k) dst[size_t(x) * 6 + k] = QuantizeOne(src[size_t(x) * stride + k], inv_scale[k], bias[k]);
}

#pragma GCC diagnostic pop

}  // namespace

CoefficientRange CoefficientRange::Empty() {
  CoefficientRange range;
  range.lo.fill(std::numeric_limits<float>::infinity());
  range.hi.fill(-std::numeric_limits<float>::infinity());
  return range;
}

void CoefficientRange::Include(const CoefficientRange& other) {
  for (int k = 0; k < 6; ++k) lo[k] = std::min(lo[k], other.lo[k]), hi[k] = std::max(hi[k], other.hi[k]);
  finite = finite && other.finite;
}

CoefficientRange RowCoefficientRange(const float* values, int count) { return RangeKernel(values, count); }

void QuantizeCoefficients(const float* src, int stride, int pixels, const double inv_scale[6], const int bias[6],
                          unsigned char* dst) {
  QuantizeKernel(src, stride, pixels, inv_scale, bias, dst);
}

}  // namespace mesocap
