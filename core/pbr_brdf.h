// The glTF 2.0 metallic-roughness BRDF (glTF specification, Appendix B): Lambertian diffuse and a
// GGX specular lobe with the separable Smith visibility, mixed by Schlick's Fresnel for
// dielectrics (F0 = 0.04) and tinted by the base colour for metals. Templated on the scalar so
// Ceres differentiates it (the GGX fit, export/ggx_fit.h) and the virtual rig renders its `ggx`
// material with exactly what a glTF viewer would show.
#pragma once

#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/Core>

namespace mesocap {

struct PbrMaterial {
  Eigen::Vector3d base_color = Eigen::Vector3d::Constant(0.5);  // linear
  double roughness = 0.5;  // perceptual; GGX alpha = roughness^2
  double metallic = 0;
};

// What depends only on the light and view directions (unit vectors `l` to the light, `v` to the
// viewer): computed once per direction pair, not per evaluation of a fit.
struct PbrGeometry {
  Eigen::Vector3d l, v, h;  // h: the half vector
  double schlick = 0;       // (1 - v.h)^5, Schlick's Fresnel weight
  PbrGeometry(const Eigen::Vector3d& light, const Eigen::Vector3d& view)
      : l(light), v(view), h((light + view).normalized()), schlick(std::pow(1 - std::max(0.0, view.dot(h)), 5)) {}
};

// The reflectance below is affine in each channel of the base colour: f_c = a b_c + b. These
// are a and b, which depend on everything else. A fit solves the base colour in closed form from
// them (variable projection).
template <typename T>
struct PbrAffine {
  T a, b;
};

template <typename T>
PbrAffine<T> PbrAffineTerms(const T& roughness, const T& metallic, const Eigen::Matrix<T, 3, 1>& n, const PbrGeometry& g) {
  using std::sqrt;
  // Products with the (constant) directions in doubles: cheap for Ceres's Jets.
  const T nl = n[0] * g.l[0] + n[1] * g.l[1] + n[2] * g.l[2];
  const T nv = n[0] * g.v[0] + n[1] * g.v[1] + n[2] * g.v[2];
  if (!(nl > T(0)) || !(nv > T(0))) return {T(0), T(0)};
  const T nh = n[0] * g.h[0] + n[1] * g.h[1] + n[2] * g.h[2];
  const T alpha = roughness * roughness, a2 = alpha * alpha;
  const T d_denominator = nh * nh * (a2 - T(1)) + T(1);
  const T D = a2 / (std::numbers::pi * d_denominator * d_denominator);
  const T visibility = T(1) / ((nl + sqrt(a2 + (T(1) - a2) * nl * nl)) * (nv + sqrt(a2 + (T(1) - a2) * nv * nv)));
  const T specular = D * visibility;
  const double fresnel = 0.04 + 0.96 * g.schlick;  // dielectric
  // Dielectric: (1 - F) base / pi + F specular. Metal: specular (base + (1 - base) schlick).
  const T a = (T(1) - metallic) * ((1 - fresnel) / std::numbers::pi) + metallic * specular * (1 - g.schlick);
  const T b = ((T(1) - metallic) * fresnel + metallic * g.schlick) * specular;
  return {a * nl, b * nl};
}

// BRDF times the cosine of the light to `n`: the reflected radiance per unit irradiance
// perpendicular to the light, what a BTF slice holds (docs/formats.md). `n` is the unit normal.
// Zero when the light or the viewer is below the surface.
template <typename T>
Eigen::Matrix<T, 3, 1> PbrReflectance(const Eigen::Matrix<T, 3, 1>& base_color, const T& roughness, const T& metallic,
                                      const Eigen::Matrix<T, 3, 1>& n, const PbrGeometry& g) {
  const PbrAffine<T> terms = PbrAffineTerms(roughness, metallic, n, g);
  Eigen::Matrix<T, 3, 1> f;
  for (int c = 0; c < 3; ++c) f[c] = terms.a * base_color[c] + terms.b;
  return f;
}

inline Eigen::Vector3d PbrReflectance(const PbrMaterial& m, const Eigen::Vector3d& n, const Eigen::Vector3d& l,
                                      const Eigen::Vector3d& v) {
  return PbrReflectance<double>(m.base_color, m.roughness, m.metallic, n, PbrGeometry(l, v));
}

}  // namespace mesocap
