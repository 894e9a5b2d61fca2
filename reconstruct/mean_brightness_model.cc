#include "reconstruct/mean_brightness_model.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

#include "core/directions.h"

namespace mesocap {
namespace {

// Below this cosine (about 87 deg) a light is too grazing to divide by its cosine.
constexpr double kMinCosine = 0.05;
// Ridge weight per sample on every term but the constant: small, it only keeps terms the lights
// do not separate from growing without bound (0 to 1e-2 measured on seeds 11-13; 1e-4 best).
constexpr double kRidge = 1e-4;
// The width of the measured pairs whose log error is added back (measured on seeds 11-13: 8 and
// 25 deg do about as well).
constexpr double kResidualWidthDeg = 15.0;

}  // namespace

std::array<double, MeanBrightnessModel::kTerms> MeanBrightnessModel::Terms(const Eigen::Vector3d& light,
                                                                           const Eigen::Vector3d& view) {
  const Eigen::Vector3d l = light.normalized(), v = view.normalized(), h = (l + v).normalized();
  const double cos_i = l.z(), cos_o = v.z();
  // Oren-Nayar's term: max(0, cos(phi_i - phi_o)) sin(alpha) tan(beta), alpha and beta the larger
  // and smaller of the two elevations' angles.
  const double l_planar = l.head<2>().norm(), v_planar = v.head<2>().norm();
  const double cos_azimuth = l_planar > 1e-6 && v_planar > 1e-6 ? l.head<2>().dot(v.head<2>()) / (l_planar * v_planar) : 0.0;
  const double theta_i = std::acos(std::clamp(cos_i, -1.0, 1.0)), theta_o = std::acos(std::clamp(cos_o, -1.0, 1.0));
  const double oren_nayar =
      std::max(0.0, cos_azimuth) * std::sin(std::max(theta_i, theta_o)) * std::tan(std::min(theta_i, theta_o));
  return {1.0,
          cos_i,
          cos_o,
          l.dot(v),
          h.z(),
          h.z() * h.z(),
          cos_i * cos_o,
          oren_nayar,
          l.x() * v.x(),
          l.y() * v.y(),
          l.x() * v.y(),
          l.y() * v.x(),
          l.x() * l.x() - l.y() * l.y(),
          v.x() * v.x() - v.y() * v.y(),
          l.x() * l.y(),
          v.x() * v.y(),
          h.x() * h.x() - h.y() * h.y(),
          h.x() * h.y()};
}

MeanBrightnessModel MeanBrightnessModel::Fit(const std::vector<MeanBrightnessSample>& samples) {
  MeanBrightnessModel model;
  for (const MeanBrightnessSample& s : samples)
    if (s.brightness > 0 && std::isfinite(s.brightness) && s.light.normalized().z() >= kMinCosine)
      model.samples_.push_back({s.light.normalized(), s.view.normalized(), s.brightness});
  const int n = int(model.samples_.size());
  if (n < 2 * kTerms) return model;
  Eigen::Matrix<double, kTerms, kTerms> normal = Eigen::Matrix<double, kTerms, kTerms>::Zero();
  Eigen::Matrix<double, kTerms, 1> rhs = Eigen::Matrix<double, kTerms, 1>::Zero();
  for (const MeanBrightnessSample& s : model.samples_) {
    const auto terms = Terms(s.light, s.view);
    const Eigen::Map<const Eigen::Matrix<double, kTerms, 1>> t(terms.data());
    normal += t * t.transpose();
    rhs += t * std::log(s.brightness / s.light.z());
  }
  for (int k = 1; k < kTerms; ++k) normal(k, k) += kRidge * n;
  model.coefficients_ = normal.ldlt().solve(rhs);
  if (!model.coefficients_.allFinite()) return MeanBrightnessModel();
  for (const MeanBrightnessSample& s : model.samples_) {
    model.residuals_.push_back(std::log(s.brightness / s.light.z()) - model.LogRadianceOverCosine(s.light, s.view));
    const auto known = std::find(model.views_.begin(), model.views_.end(), s.view);
    model.sample_view_.push_back(int(known - model.views_.begin()));
    if (known == model.views_.end()) model.views_.push_back(s.view);
  }
  model.fitted_ = true;
  return model;
}

double MeanBrightnessModel::LogRadianceOverCosine(const Eigen::Vector3d& light, const Eigen::Vector3d& view) const {
  const auto terms = Terms(light, view);
  return Eigen::Map<const Eigen::Matrix<double, kTerms, 1>>(terms.data()).dot(coefficients_);
}

double MeanBrightnessModel::Predict(const Eigen::Vector3d& light, const Eigen::Vector3d& view) const {
  const Eigen::Vector3d l = light.normalized(), v = view.normalized();
  if (!fitted_ || l.z() < kMinCosine) return 0;
  // The residuals of the measured pairs, weighted by a Gaussian of their view's and light's
  // angles to the pair's; far from every measured pair, the nearest ones (the weights relative to
  // the largest).
  std::vector<double> view_exponents(views_.size());
  for (size_t j = 0; j < views_.size(); ++j) {
    const double dv = AngleBetweenDeg(v, views_[j]) / kResidualWidthDeg;
    view_exponents[j] = dv * dv;
  }
  std::vector<double> exponents(samples_.size());
  double nearest = 1e300;
  for (size_t k = 0; k < samples_.size(); ++k) {
    const double dl = AngleBetweenDeg(l, samples_[k].light) / kResidualWidthDeg;
    exponents[k] = view_exponents[size_t(sample_view_[k])] + dl * dl;
    nearest = std::min(nearest, exponents[k]);
  }
  double weights = 0, residual = 0;
  for (size_t k = 0; k < samples_.size(); ++k) {
    const double w = std::exp(-(exponents[k] - nearest));
    weights += w;
    residual += w * residuals_[k];
  }
  return std::exp(LogRadianceOverCosine(l, v) + residual / weights) * l.z();
}

}  // namespace mesocap
