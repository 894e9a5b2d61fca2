// The white specular part of a material's mean radiance, as one GGX lobe fitted to the measured
// slices' mean colours. A dielectric's specular reflection is white while its body colour is not
// (Shafer's dichromatic reflection model), so each slice's mean RGB splits into a body-coloured
// part and a white part; the white parts of all views are fitted by
// k D(h) F(l.h) G(l) G(v) / (4 cos theta_v) (the slices' radiance includes cos theta_i). The lobe
// predicts what no view measured: the whitening near a tilted view's mirror direction (every
// board sees the hand-held flash from the camera's side).
#pragma once

#include <vector>

#include <Eigen/Core>

#include "core/json.h"

namespace mesocap {

struct MeanColourSample {
  Eigen::Vector3d light, view;  // unit, patch frame
  Eigen::Vector3d mean_rgb;     // the slice's mean linear RGB
};

class WhiteLobe {
 public:
  // Fits the lobe to `samples`; a lobe of zero strength when they are fewer than kMinSamples or
  // carry no white part (a grey or a purely diffuse material).
  static constexpr size_t kMinSamples = 6;
  // Strength 1 is a smooth dielectric's (F0 = 0.04) whole specular reflection; mesostructure only
  // spreads it. A fit stronger than this is taken as a failed split and gives a lobe of zero
  // strength (the virtual weave, body chromaticity (0.32, 0.32, 0.37), fits 9.4; stones 1.6).
  static constexpr double kMaxStrength = 2.0;
  static WhiteLobe Fit(const std::vector<MeanColourSample>& samples);

  // The white part's mean radiance at (light, view), per colour channel.
  double Radiance(const Eigen::Vector3d& light, const Eigen::Vector3d& view) const;
  // The lobe of unit strength and roughness `alpha` (unit directions).
  static double Shape(const Eigen::Vector3d& light, const Eigen::Vector3d& view, double alpha);
  // The white part of one mean colour, given the body colour (chromaticity, sums to 1).
  static double WhitePart(const Eigen::Vector3d& mean_rgb, const Eigen::Vector3d& body_chromaticity);

  double strength() const { return strength_; }
  double alpha() const { return alpha_; }
  const Eigen::Vector3d& body_chromaticity() const { return body_; }
  // {"strength", "alpha", "body_chromaticity": [r, g, b]} for reports (strength 0: no lobe).
  Json ToJson() const;

 private:
  // The roughness and strength of the lobe fitted to the white parts of `samples` under body_.
  void FitLobe(const std::vector<MeanColourSample>& samples);
  double strength_ = 0, alpha_ = 0.3;
  Eigen::Vector3d body_ = Eigen::Vector3d::Constant(1.0 / 3);
};

}  // namespace mesocap
