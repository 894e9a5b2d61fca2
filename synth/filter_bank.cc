#include "synth/filter_bank.h"

#include <cmath>

#include "core/fftw_buffers.h"
#include "core/status.h"

namespace mesocap {
namespace {

constexpr int kHalf = kFilterSupport / 2;
constexpr double kPi = 3.14159265358979323846;

// Texel (x, y) of a kernel given by value(u, v) at offsets from its centre.
template <typename Fn>
std::vector<float> Kernel(Fn value) {
  std::vector<float> k(size_t(kFilterSupport) * kFilterSupport);
  for (int y = -kHalf; y <= kHalf; ++y)
    for (int x = -kHalf; x <= kHalf; ++x) k[size_t(y + kHalf) * kFilterSupport + x + kHalf] = float(value(x, y));
  return k;
}

std::vector<float> ZeroMeanUnitL1(std::vector<float> k) {
  double mean = 0, l1 = 0;
  for (float v : k) mean += v;
  mean /= double(k.size());
  for (float& v : k) l1 += std::abs(v -= float(mean));
  for (float& v : k) v = float(v / l1);
  return k;
}

std::vector<float> UnitSum(std::vector<float> k) {
  double sum = 0;
  for (float v : k) sum += v;
  for (float& v : k) v = float(v / sum);
  return k;
}

// Derivative of order 1 or 2 across an elongated Gaussian (sigma along the edge 3x across) whose
// long axis is turned by `angle` from x.
std::vector<float> OrientedDerivative(double sigma, double angle, int order) {
  const double along = 3 * sigma, across = sigma, c = std::cos(angle), s = std::sin(angle);
  return ZeroMeanUnitL1(Kernel([&](int x, int y) {
    const double u = x * c + y * s, v = -x * s + y * c;
    const double g = std::exp(-u * u / (2 * along * along) - v * v / (2 * across * across));
    return order == 1 ? -v / (across * across) * g : (v * v / std::pow(across, 4) - 1 / (across * across)) * g;
  }));
}

std::vector<float> LaplacianOfGaussian(double sigma) {
  return ZeroMeanUnitL1(Kernel([&](int x, int y) {
    const double r2 = double(x) * x + double(y) * y;
    return (r2 - 2 * sigma * sigma) / std::pow(sigma, 4) * std::exp(-r2 / (2 * sigma * sigma));
  }));
}

std::vector<float> Gaussian(double sigma) {
  return UnitSum(Kernel([&](int x, int y) { return std::exp(-(double(x) * x + double(y) * y) / (2 * sigma * sigma)); }));
}

// Index into [0, n) reflecting at both ends as often as needed (images smaller than the support).
int Mirror(int i, int n) {
  const int period = 2 * n;
  i %= period;
  if (i < 0) i += period;
  return i < n ? i : period - 1 - i;
}

}  // namespace

std::vector<std::vector<float>> LeungMalikFilters() {
  std::vector<std::vector<float>> bank;
  const double root2 = std::sqrt(2.0);
  for (int order = 1; order <= 2; ++order)
    for (double sigma : {root2, 2.0, 2 * root2})
      for (int o = 0; o < 6; ++o) bank.push_back(OrientedDerivative(sigma, kPi * o / 6, order));
  for (double sigma : {root2, 2.0, 2 * root2, 4.0}) bank.push_back(LaplacianOfGaussian(sigma));
  for (double sigma : {root2, 2.0, 2 * root2, 4.0}) bank.push_back(LaplacianOfGaussian(3 * sigma));
  for (double sigma : {root2, 2.0, 2 * root2, 4.0}) bank.push_back(Gaussian(sigma));
  return bank;
}

struct FilterBank::Impl {
  int width = 0, height = 0, fft_width = 0, fft_height = 0;
  size_t spectrum_size = 0;
  fftwf_plan forward = nullptr, inverse = nullptr;
  std::vector<FftComplexBuffer> spectra;  // one per filter, already divided by the FFT's size
};

FilterBank::FilterBank(int width, int height) : impl_(std::make_unique<Impl>()) {
  MESOCAP_CHECK(width > 0 && height > 0, "filter bank on an empty image");
  Impl& m = *impl_;
  m.width = width, m.height = height;
  m.fft_width = FftFriendlySize(width + 2 * kHalf), m.fft_height = FftFriendlySize(height + 2 * kHalf);
  m.spectrum_size = size_t(m.fft_height) * (m.fft_width / 2 + 1);
  FftFloatBuffer plane(size_t(m.fft_width) * m.fft_height);
  const RealFftPlans& plans = RealFftPlansFor(m.fft_width, m.fft_height);
  m.forward = plans.forward;
  m.inverse = plans.inverse;
  const float scale = 1.0f / (float(m.fft_width) * m.fft_height);
  for (const std::vector<float>& kernel : LeungMalikFilters()) {
    std::fill_n(plane.data, size_t(m.fft_width) * m.fft_height, 0.f);
    for (int y = -kHalf; y <= kHalf; ++y)  // centre at (0, 0), wrapped: a convolution, no shift
      for (int x = -kHalf; x <= kHalf; ++x)
        plane.data[size_t((y + m.fft_height) % m.fft_height) * m.fft_width + (x + m.fft_width) % m.fft_width] =
            kernel[size_t(y + kHalf) * kFilterSupport + x + kHalf] * scale;
    FftComplexBuffer spectrum(m.spectrum_size);
    fftwf_execute_dft_r2c(m.forward, plane.data, spectrum.fftw());
    m.spectra.push_back(std::move(spectrum));
  }
}

FilterBank::~FilterBank() = default;

Image FilterBank::Responses(const Image& luminance) const {
  const Impl& m = *impl_;
  MESOCAP_CHECK(luminance.width() == m.width && luminance.height() == m.height && luminance.channels() == 1,
                "filter bank applied to an image of another size");
  // The image mirrored into the padded plane: the wrap-around of the circular convolution then
  // only mixes the padding, never the image's far side into its near side.
  FftFloatBuffer plane(size_t(m.fft_width) * m.fft_height);
  for (int y = 0; y < m.height + 2 * kHalf; ++y)
    for (int x = 0; x < m.width + 2 * kHalf; ++x)
      plane.data[size_t(y) * m.fft_width + x] = luminance.at(Mirror(x - kHalf, m.width), Mirror(y - kHalf, m.height));
  FftComplexBuffer image_spectrum(m.spectrum_size), product(m.spectrum_size);
  fftwf_execute_dft_r2c(m.forward, plane.data, image_spectrum.fftw());
  Image out = Image::Uninitialized(m.width, m.height, kFilterBankSize);
  for (int k = 0; k < kFilterBankSize; ++k) {
    const FftComplex* f = m.spectra[k].data;
    for (size_t i = 0; i < m.spectrum_size; ++i) product.data[i] = image_spectrum.data[i] * f[i];
    fftwf_execute_dft_c2r(m.inverse, product.fftw(), plane.data);
    for (int y = 0; y < m.height; ++y)
      for (int x = 0; x < m.width; ++x) out.at(x, y, k) = plane.data[size_t(y + kHalf) * m.fft_width + x + kHalf];
  }
  return out;
}

}  // namespace mesocap
