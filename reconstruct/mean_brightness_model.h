// A model of a material's mean brightness over light and view directions, fitted to the mean of
// every measured slice, for the pairs whose light no view near them measured. A tilted board sees
// the hand-held flash from the camera's side only, so far from its measured lights the statistical
// BTF falls back on the top view's statistics at the light, and the mean radiance a tilted view
// has there is what it gets most wrong (bench_session_coverage --true-mean 1).
//
// log(mean / cos theta_i) is a linear function of 18 terms of the light l and view v (unit, patch
// frame, h their half vector): the isotropic ones (1, cos theta_i, cos theta_o, their product,
// l.v, h's elevation cosine and its square, Oren-Nayar's retro-reflection term), and products of
// the x and y components of l, v and h, which carry a grain's anisotropy. Fitted by ridge least
// squares. At a pair, the model's log errors at the measured pairs are added back, weighted by a
// Gaussian (15 deg) of their view's and light's angles to the pair's: near measured pairs their
// errors, so where slices were measured it reproduces them; far from all, the nearest pairs'.
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>

namespace mesocap {

struct MeanBrightnessSample {
  Eigen::Vector3d light, view;  // unit, patch frame
  double brightness = 0;        // the slice's mean, > 0
};

class MeanBrightnessModel {
 public:
  static constexpr int kTerms = 18;

  // Unfitted (too few usable samples: fewer than twice the terms) models predict nothing.
  static MeanBrightnessModel Fit(const std::vector<MeanBrightnessSample>& samples);

  bool fitted() const { return fitted_; }
  // The predicted mean brightness at (light, view); 0 when not fitted or the light is below the
  // horizon.
  double Predict(const Eigen::Vector3d& light, const Eigen::Vector3d& view) const;

 private:
  static std::array<double, kTerms> Terms(const Eigen::Vector3d& light, const Eigen::Vector3d& view);
  double LogRadianceOverCosine(const Eigen::Vector3d& light, const Eigen::Vector3d& view) const;
  bool fitted_ = false;
  Eigen::Matrix<double, kTerms, 1> coefficients_ = Eigen::Matrix<double, kTerms, 1>::Zero();
  std::vector<MeanBrightnessSample> samples_;
  std::vector<double> residuals_;  // log(measured) - log(model), per sample
  // The samples' distinct views, and each sample's among them: Predict measures the angle to each
  // view once, not once per light (a view's images multiply its lights).
  std::vector<Eigen::Vector3d> views_;
  std::vector<int> sample_view_;
};

}  // namespace mesocap
