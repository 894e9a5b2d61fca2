#include "reconstruct/colour.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <Eigen/Eigenvalues>

#include "reconstruct/quantiles.h"

namespace mesocap {
namespace {

constexpr float kLargestHalf = 65504.0f;

Image Transformed(const Image& image, const Eigen::Matrix3f& m) {
  if (image.channels() != 3) return image;
  Image out(image.width(), image.height(), 3);
  const float* src = image.data();
  float* dst = out.data();
  for (size_t i = 0; i < image.pixel_count(); ++i) {
    Eigen::Map<Eigen::Vector3f>(dst + 3 * i) = m * Eigen::Map<const Eigen::Vector3f>(src + 3 * i);
  }
  return out;
}

}  // namespace

Eigen::Matrix3f DecorrelatingColourBasis(std::span<const Image> images) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  Eigen::Matrix3d outer = Eigen::Matrix3d::Zero();
  double n = 0;
  for (const Image& image : images) {
    if (image.empty()) continue;
    if (image.channels() != 3) return Eigen::Matrix3f::Identity();
    // About 64k texels per image are plenty for a 3x3 covariance.
    const size_t stride = std::max<size_t>(1, image.pixel_count() / 65536);
    for (size_t i = 0; i < image.pixel_count(); i += stride) {
      const Eigen::Vector3d c = Eigen::Map<const Eigen::Vector3f>(image.data() + 3 * i).cast<double>();
      if (!c.allFinite()) continue;
      sum += c;
      outer += c * c.transpose();
      ++n;
    }
  }
  if (n < 2) return Eigen::Matrix3f::Identity();
  const Eigen::Vector3d mean = sum / n;
  const Eigen::Matrix3d covariance = outer / n - mean * mean.transpose();
  if (!(covariance.trace() > 0)) return Eigen::Matrix3f::Identity();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
  Eigen::Matrix3d basis;
  for (int r = 0; r < 3; ++r) {  // eigenvalues come in increasing order
    Eigen::Vector3d axis = solver.eigenvectors().col(2 - r);
    Eigen::Index largest;
    axis.cwiseAbs().maxCoeff(&largest);
    if (axis(largest) < 0) axis = -axis;
    basis.row(r) = axis.transpose();
  }
  return basis.cast<float>();
}

ColourChannels ColourChannels::For(ColourSpace space, std::span<const Image> top_slices) {
  ColourChannels c;
  c.space_ = space;
  if (space == ColourSpace::kPrincipalAxes) c.basis_ = DecorrelatingColourBasis(top_slices);
  return c;
}

Image ColourChannels::Forward(const Image& rgb) const {
  if (rgb.channels() != 3 || space_ == ColourSpace::kRgb) return rgb;
  if (space_ == ColourSpace::kPrincipalAxes) return Transformed(rgb, basis_);
  Image out(rgb.width(), rgb.height(), 3);
  for (size_t i = 0; i < rgb.pixel_count(); ++i) {
    const float* c = rgb.data() + 3 * i;
    float* d = out.data() + 3 * i;
    d[0] = c[0] + c[1] + c[2];
    if (!Chromaticity(c, &d[1], &d[2])) d[1] = d[2] = 1.0f / 3;  // black has no colour: call it grey
  }
  return out;
}

Image ColourChannels::Inverse(const Image& channels) const {
  Image out;
  if (channels.channels() != 3 || space_ == ColourSpace::kRgb) {
    out = channels;
  } else if (space_ == ColourSpace::kPrincipalAxes) {
    out = Transformed(channels, basis_.transpose());
  } else {
    out = Image(channels.width(), channels.height(), 3);
    for (size_t i = 0; i < channels.pixel_count(); ++i) {
      const float* c = channels.data() + 3 * i;
      float* d = out.data() + 3 * i;
      d[0] = c[1] * c[0];
      d[1] = c[2] * c[0];
      d[2] = (1 - c[1] - c[2]) * c[0];
    }
  }
  ClampToStorableRadiance(&out);
  return out;
}

bool Chromaticity(const float* rgb, float* r, float* g) {
  const float total = rgb[0] + rgb[1] + rgb[2];
  if (!(total > 0 && std::isfinite(total))) return false;
  *r = rgb[0] / total;
  *g = rgb[1] / total;
  return true;
}

void ClampToStorableRadiance(Image* image) {
  for (float& v : std::span(image->data(), image->size())) v = std::isfinite(v) ? std::clamp(v, 0.0f, kLargestHalf) : 0.0f;
}

double ChromaticityDistance(const Image& a, const Image& b) {
  if (a.channels() != 3 || b.channels() != 3) return 0;
  auto chromaticities = [](const Image& image, int channel) {
    std::vector<float> values;
    values.reserve(image.pixel_count());
    float rg[2];
    for (size_t i = 0; i < image.pixel_count(); ++i)
      if (Chromaticity(image.data() + 3 * i, &rg[0], &rg[1])) values.push_back(rg[channel]);
    return values;
  };
  double distance = 0;
  for (int channel = 0; channel < 2; ++channel) {
    const std::vector<float> va = chromaticities(a, channel), vb = chromaticities(b, channel);
    if (va.empty() || vb.empty()) return va.empty() == vb.empty() ? 0 : 1;
    distance += 0.5 * WassersteinDistance(InverseCdfOf(va), InverseCdfOf(vb));
  }
  return distance;
}

double SaturationQuantile(const Image& image, double q) {
  if (image.channels() != 3) return 0;
  std::vector<float> saturation;
  saturation.reserve(image.pixel_count());
  for (size_t i = 0; i < image.pixel_count(); ++i) {
    const float* c = image.data() + 3 * i;
    const float hi = std::max({c[0], c[1], c[2]}), lo = std::min({c[0], c[1], c[2]});
    if (hi > 0 && std::isfinite(hi)) saturation.push_back((hi - std::max(lo, 0.0f)) / hi);
  }
  if (saturation.empty()) return 0;
  return InverseCdfOf(saturation, 1001).At(q);
}

}  // namespace mesocap
