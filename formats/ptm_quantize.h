// The .ptm writer's per-row work, vectorised (core/simd.h): the range and finiteness of a row's
// coefficients, and their quantisation to bytes. Both give exactly what the plain loops do
// (min/max are exact; the quantisation rounds each product and sum as the scalar code does).
#pragma once

#include <array>

namespace mesocap {

struct CoefficientRange {
  std::array<float, 6> lo, hi;  // per coefficient index k
  bool finite = true;           // no inf or NaN among the values

  static CoefficientRange Empty();  // lo = +inf, hi = -inf: includes nothing yet
  void Include(const CoefficientRange& other);
};

// Over values[0..count), count a multiple of 6, coefficient index k = i % 6.
CoefficientRange RowCoefficientRange(const float* values, int count);

// For pixels x < pixels, the 6 coefficients at src + x * stride: dst[6x + k] =
// clamp(round_half_even(clamp(255 * src[k] * inv_scale[k] + bias[k], -1, 256)), 0, 255), each
// product and sum in double. Values must be finite.
void QuantizeCoefficients(const float* src, int stride, int pixels, const double inv_scale[6], const int bias[6],
                          unsigned char* dst);

}  // namespace mesocap
