// The Leung-Malik bank of 48 Gaussian-derivative filters that 3D textons are built from (Leung &
// Malik 2001, used by Tong et al. 2002 §4 with n_b = 48): first and second derivatives of an
// elongated Gaussian (3:1) at 6 orientations and 3 scales (36), 8 Laplacians of Gaussians and 4
// Gaussians, on a 49 x 49 support. Responses are computed by FFT with the filters' spectra made
// once per image size; the image is mirrored at its border, not wrapped.
#pragma once

#include <memory>
#include <vector>

#include "core/image.h"

namespace mesocap {

inline constexpr int kFilterBankSize = 48;   // n_b
inline constexpr int kFilterSupport = 49;    // texels a side

// The 48 kernels, kFilterSupport^2 values each, row-major. Derivative and Laplacian kernels have
// zero mean and unit L1 norm (they respond to structure, not to the level); the Gaussians sum to 1
// (they carry the local shading level, which a BTF's appearance depends on).
std::vector<std::vector<float>> LeungMalikFilters();

// Applies the bank to one-channel images of one size. Thread-safe once built.
class FilterBank {
 public:
  FilterBank(int width, int height);
  ~FilterBank();
  FilterBank(const FilterBank&) = delete;
  FilterBank& operator=(const FilterBank&) = delete;
  // width x height x 48: response k of texel (x, y) at channel k.
  Image Responses(const Image& luminance) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace mesocap
