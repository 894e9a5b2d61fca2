// A PTM's biquadratic in the orthonormal 2D Legendre basis (the PTM synthesis paper, §VI): on
// the square [-1, 1]^2 of (lu, lv), the basis
//   psi_0 = 1/2, psi_1 = (sqrt 3 / 2) lu, psi_2 = (sqrt 3 / 2) lv, psi_3 = (3/2) lu lv,
//   psi_4 = (sqrt 5 / 4)(3 lu^2 - 1), psi_5 = (sqrt 5 / 4)(3 lv^2 - 1)
// is orthonormal and spans the same polynomials as the PTM terms [lu^2, lv^2, lu lv, lu, lv, 1]
// (reconstruct/ptm.h). So the Euclidean distance between two coefficient vectors in this basis is
// the L2 distance between the two reflectance functions over that square, and averaging or
// blending coefficients averages the functions: block synthesis compares and cuts PTM texels in
// this basis.
#pragma once

#include <Eigen/Core>

#include "core/image.h"
#include "reconstruct/ptm.h"

namespace mesocap {

// b = M a: PTM coefficients a (ptm.h order) to Legendre coefficients b (psi order above).
const Eigen::Matrix<double, 6, 6>& PtmToLegendreMatrix();
// a = M^-1 b.
const Eigen::Matrix<double, 6, 6>& LegendreToPtmMatrix();

// The 6 basis values psi_0..psi_5 at (lu, lv).
Eigen::Matrix<double, 6, 1> LegendreBasis(double lu, double lv);

// Per texel, each colour channel's reflectance function in the Legendre basis: 18 channels,
// psi_0..psi_5 of red, then green, then blue (an LRGB PTM's channel c is rgb_c times its
// luminance polynomial).
Image PtmLegendreCoefficients(const Ptm& ptm);

// The RGB PTM with those per-channel Legendre coefficients (18 channels, as above).
Ptm PtmFromLegendreCoefficients(const Image& legendre);

}  // namespace mesocap
