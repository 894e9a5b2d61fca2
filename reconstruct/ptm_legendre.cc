#include "reconstruct/ptm_legendre.h"

#include <Eigen/LU>
#include <cmath>

#include "core/status.h"

namespace mesocap {

const Eigen::Matrix<double, 6, 6>& PtmToLegendreMatrix() {
  // Each PTM term in the basis: 1 = 2 psi_0; lu = (2/sqrt 3) psi_1; lv = (2/sqrt 3) psi_2;
  // lu lv = (2/3) psi_3; lu^2 = (4/(3 sqrt 5)) psi_4 + (2/3) psi_0; likewise lv^2 with psi_5.
  static const Eigen::Matrix<double, 6, 6> m = [] {
    Eigen::Matrix<double, 6, 6> to = Eigen::Matrix<double, 6, 6>::Zero();  // column k: term a_k
    const double s3 = std::sqrt(3.0), s5 = std::sqrt(5.0);
    to(0, 0) = 2.0 / 3, to(4, 0) = 4 / (3 * s5);  // lu^2
    to(0, 1) = 2.0 / 3, to(5, 1) = 4 / (3 * s5);  // lv^2
    to(3, 2) = 2.0 / 3;                           // lu lv
    to(1, 3) = 2 / s3;                            // lu
    to(2, 4) = 2 / s3;                            // lv
    to(0, 5) = 2;                                 // 1
    return to;
  }();
  return m;
}

const Eigen::Matrix<double, 6, 6>& LegendreToPtmMatrix() {
  static const Eigen::Matrix<double, 6, 6> m = PtmToLegendreMatrix().inverse();
  return m;
}

Eigen::Matrix<double, 6, 1> LegendreBasis(double lu, double lv) {
  const double s3 = std::sqrt(3.0), s5 = std::sqrt(5.0);
  Eigen::Matrix<double, 6, 1> psi;
  psi << 0.5, s3 / 2 * lu, s3 / 2 * lv, 1.5 * lu * lv, s5 / 4 * (3 * lu * lu - 1), s5 / 4 * (3 * lv * lv - 1);
  return psi;
}

Image PtmLegendreCoefficients(const Ptm& ptm) {
  MESOCAP_CHECK(ptm.IsConsistent(), "inconsistent Ptm");
  const Eigen::Matrix<double, 6, 6>& m = PtmToLegendreMatrix();
  const bool lrgb = ptm.format == PtmFormat::kLrgb;
  Image out(ptm.width(), ptm.height(), 3 * kPtmCoefficients);
  for (int y = 0; y < ptm.height(); ++y)
    for (int x = 0; x < ptm.width(); ++x) {
      const float* a = ptm.coefficients.pixel(x, y);
      float* b = out.pixel(x, y);
      for (int c = 0; c < 3; ++c) {
        Eigen::Matrix<double, 6, 1> ac;
        for (int k = 0; k < kPtmCoefficients; ++k)
          ac[k] = lrgb ? double(a[k]) * ptm.rgb.at(x, y, c) : double(a[kPtmCoefficients * c + k]);
        const Eigen::Matrix<double, 6, 1> bc = m * ac;
        for (int k = 0; k < kPtmCoefficients; ++k) b[kPtmCoefficients * c + k] = float(bc[k]);
      }
    }
  return out;
}

Ptm PtmFromLegendreCoefficients(const Image& legendre) {
  MESOCAP_CHECK(legendre.channels() == 3 * kPtmCoefficients, "Legendre coefficients need 18 channels");
  const Eigen::Matrix<double, 6, 6>& m = LegendreToPtmMatrix();
  Ptm ptm;
  ptm.format = PtmFormat::kRgb;
  ptm.coefficients = Image(legendre.width(), legendre.height(), 3 * kPtmCoefficients);
  for (int y = 0; y < legendre.height(); ++y)
    for (int x = 0; x < legendre.width(); ++x) {
      const float* b = legendre.pixel(x, y);
      float* a = ptm.coefficients.pixel(x, y);
      for (int c = 0; c < 3; ++c) {
        Eigen::Matrix<double, 6, 1> bc;
        for (int k = 0; k < kPtmCoefficients; ++k) bc[k] = b[kPtmCoefficients * c + k];
        const Eigen::Matrix<double, 6, 1> ac = m * bc;
        for (int k = 0; k < kPtmCoefficients; ++k) a[kPtmCoefficients * c + k] = float(ac[k]);
      }
    }
  return ptm;
}

}  // namespace mesocap
