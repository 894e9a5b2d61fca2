// Colour for the statistical BTF: the decorrelated colour space its histograms are matched in
// (Heeger & Bergen 1995's colour extension: principal axes of the sample's colours, so that
// matching each axis on its own does not invent colours the way matching R, G and B on their own
// does), and the colour measures a reconstruction is scored on against the truth.
#pragma once

#include <optional>
#include <span>
#include <string>

#include <Eigen/Core>

#include "core/image.h"
#include "reconstruct/colour_space.h"

namespace mesocap {

class ColourChannels {
 public:
  ColourChannels() = default;  // RGB
  // The principal axes come from `top_slices` (empty images are skipped).
  static ColourChannels For(ColourSpace space, std::span<const Image> top_slices);
  // Channels as For made them (a statistics record read back).
  static ColourChannels WithBasis(ColourSpace space, const Eigen::Matrix3f& basis) {
    ColourChannels c;
    c.space_ = space, c.basis_ = basis;
    return c;
  }
  ColourSpace space() const { return space_; }
  const Eigen::Matrix3f& basis() const { return basis_; }
  Image Forward(const Image& rgb) const;
  // Back to RGB, as storable radiance (ClampToStorableRadiance).
  Image Inverse(const Image& channels) const;
  // False for a channel that does not scale with the light's irradiance (a chromaticity).
  bool ScalesWithRadiance(int channel) const { return space_ != ColourSpace::kChromaticity || channel == 0; }

 private:
  ColourSpace space_ = ColourSpace::kRgb;
  Eigen::Matrix3f basis_ = Eigen::Matrix3f::Identity();  // kPrincipalAxes: rows are the axes
};

// Rows: the principal axes of the images' RGB colours (covariance eigenvectors, largest variance
// first, each signed so its largest component is positive). Identity unless the images have 3
// channels and some colour variance.
Eigen::Matrix3f DecorrelatingColourBasis(std::span<const Image> images);

// Radiance as it may be stored: non-finite values to 0, then clamped to [0, largest half float].
void ClampToStorableRadiance(Image* image);

// A colour's chromaticities r = R / (R + G + B), g = G / (R + G + B); false (and nothing set)
// for black or a non-finite colour, which has none.
bool Chromaticity(const float* rgb, float* r, float* g);

// W1 between the two images' chromaticity histograms: r = R / (R + G + B) and g = G / (R + G + B)
// over texels with R + G + B > 0, the mean of the two marginals' distances. 0 without 3 channels.
double ChromaticityDistance(const Image& a, const Image& b);

// The `q` quantile of the texels' HSV saturation (max - min) / max over texels with max > 0.
// 0 without 3 channels.
double SaturationQuantile(const Image& image, double q);

}  // namespace mesocap
