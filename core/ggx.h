// The GGX (Trowbridge-Reitz) microfacet lobe's three factors, in terms of alpha^2: the normal
// distribution D, Smith's separable masking G1 and Schlick's Fresnel. The virtual rig's materials
// and its billiard balls' clear coat (capture/) and the white specular lobe the reconstruction fits
// (reconstruct/white_lobe.h) are built from them; each caller keeps its own clamps and the
// 1 / (4 cos_i cos_o) it divides by. (core/pbr_brdf.h has the glTF BRDF, templated for Ceres.)
#pragma once

#include <algorithm>
#include <cmath>
#include <numbers>

namespace mesocap {

// D(h) for the cosine between the normal and the half vector.
inline double GgxDistribution(double cos_nh, double alpha2) {
  const double denom = cos_nh * cos_nh * (alpha2 - 1) + 1;
  return alpha2 / (std::numbers::pi * denom * denom);
}

// G1 for the cosine between the normal and the light or view direction.
inline double SmithG1(double cosine, double alpha2) {
  return 2 * cosine / (cosine + std::sqrt(alpha2 + (1 - alpha2) * cosine * cosine));
}

// F for the cosine between the light and the half vector: f0 + (1 - f0) (1 - cos)^5.
inline double SchlickFresnel(double f0, double cos_lh) {
  const double c = 1 - std::clamp(cos_lh, 0.0, 1.0), c2 = c * c;
  return f0 + (1 - f0) * (c2 * c2 * c);
}

}  // namespace mesocap
