#include "reconstruct/white_lobe.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

#include "core/ggx.h"

namespace mesocap {
namespace {

constexpr double kDielectricF0 = 0.04;  // glass, plastics, fibres, stone: the lobe's Fresnel shape
constexpr double kMinCos = 0.05;

// The body colour: the mean chromaticity of the most saturated twentieth of the samples, whose
// white part is the least (taken as none).
Eigen::Vector3d BodyChromaticity(const std::vector<MeanColourSample>& samples) {
  const Eigen::Vector3d white = Eigen::Vector3d::Constant(1.0 / 3);
  std::vector<std::pair<double, Eigen::Vector3d>> by_saturation;
  for (const MeanColourSample& s : samples) {
    const double sum = s.mean_rgb.sum();
    if (!(sum > 0) || !s.mean_rgb.allFinite()) continue;
    const Eigen::Vector3d c = s.mean_rgb / sum;
    by_saturation.push_back({(c - white).norm(), c});
  }
  if (by_saturation.empty()) return white;
  std::sort(by_saturation.begin(), by_saturation.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  const size_t n = std::max<size_t>(1, by_saturation.size() / 20);
  Eigen::Vector3d body = Eigen::Vector3d::Zero();
  for (size_t k = 0; k < n; ++k) body += by_saturation[k].second;
  return body / double(n);
}

}  // namespace

double WhiteLobe::WhitePart(const Eigen::Vector3d& mean_rgb, const Eigen::Vector3d& body) {
  // mean = d body + s (1, 1, 1), least squares in (d, s).
  Eigen::Matrix<double, 3, 2> a;
  a.col(0) = body;
  a.col(1).setOnes();
  const Eigen::Matrix2d ata = a.transpose() * a;
  if (std::abs(ata.determinant()) < 1e-9) return 0;  // a grey body: no white part to tell apart
  return (ata.inverse() * (a.transpose() * mean_rgb))(1);
}

double WhiteLobe::Shape(const Eigen::Vector3d& light, const Eigen::Vector3d& view, double alpha) {
  const double cos_i = light.z(), cos_o = view.z();
  if (cos_i <= 0 || cos_o <= 0) return 0;
  const Eigen::Vector3d h = (light + view).normalized();
  const double a2 = alpha * alpha;
  const double d = GgxDistribution(h.z(), a2), f = SchlickFresnel(kDielectricF0, light.dot(h));
  return d * f * SmithG1(cos_i, a2) * SmithG1(cos_o, a2) / (4 * std::max(cos_o, kMinCos));
}

Json WhiteLobe::ToJson() const {
  return {{"strength", strength_}, {"alpha", alpha_}, {"body_chromaticity", {body_.x(), body_.y(), body_.z()}}};
}

double WhiteLobe::Radiance(const Eigen::Vector3d& light, const Eigen::Vector3d& view) const {
  return strength_ > 0 ? strength_ * Shape(light.normalized(), view.normalized(), alpha_) : 0.0;
}

WhiteLobe WhiteLobe::Fit(const std::vector<MeanColourSample>& samples) {
  WhiteLobe lobe;
  if (samples.size() < kMinSamples) return lobe;
  // The body colour from the most saturated samples, taken as without white. A broad lobe
  // leaves white in those too, and the strength comes out low (alpha 0.4: about 0.7 of it).
  // Re-estimating the body from the samples less the fitted lobe recovers it on samples that
  // follow the model, but on the virtual rig's renders it drives the fit to broad lobes stronger
  // than a dielectric reflects (stones: 1.6 -> over 2, its colour then left as blended).
  lobe.body_ = BodyChromaticity(samples);
  lobe.FitLobe(samples);
  // More white than a dielectric can reflect: the split of the mean colours failed (a body colour
  // too near grey to tell white from, or a texture whose colours mix differently by direction).
  if (lobe.strength_ > kMaxStrength) lobe.strength_ = 0;
  return lobe;
}

void WhiteLobe::FitLobe(const std::vector<MeanColourSample>& samples) {
  std::vector<double> white;
  for (const MeanColourSample& s : samples) white.push_back(s.mean_rgb.allFinite() ? WhitePart(s.mean_rgb, body_) : 0.0);
  // The roughness by a search over a log grid from 0.03 to 1, the strength by linear least
  // squares at each.
  double best_error = HUGE_VAL;
  strength_ = 0;
  for (int k = 0; k <= 60; ++k) {
    const double alpha = 0.03 * std::pow(1.0 / 0.03, k / 60.0);
    double sgg = 0, sgw = 0, sww = 0;
    for (size_t j = 0; j < samples.size(); ++j) {
      const double g = Shape(samples[j].light.normalized(), samples[j].view.normalized(), alpha);
      sgg += g * g, sgw += g * white[j], sww += white[j] * white[j];
    }
    if (!(sgg > 0) || !(sgw > 0)) continue;
    const double strength = sgw / sgg, error = sww - strength * sgw;
    if (error < best_error) best_error = error, alpha_ = alpha, strength_ = strength;
  }
}

}  // namespace mesocap
