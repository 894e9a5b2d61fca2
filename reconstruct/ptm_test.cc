#include "reconstruct/ptm.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>  // core/directions.h uses cross() without including it
#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <random>

#include "core/directions.h"
#include "core/image_u8_io.h"
#include "tests/testing.h"

namespace mesocap {
namespace {

double Eval(const double a[6], const Eigen::Vector3d& l) {
  const Eigen::Matrix<double, 1, 6> b = PtmBasis(l);
  double s = 0;
  for (int k = 0; k < 6; ++k) s += a[k] * b(k);
  return s;
}

// Lights spread over the hemisphere up to 70 deg from the normal: several elevations.
std::vector<Eigen::Vector3d> RandomLights(std::mt19937& rng, int n) {
  std::uniform_real_distribution<double> theta(5, 70), phi(0, 360);
  std::vector<Eigen::Vector3d> lights;
  while (int(lights.size()) < n) {
    const Eigen::Vector3d d = DirectionFromAnglesDeg(theta(rng), phi(rng));
    bool far = true;
    for (const auto& o : lights) far &= AngleBetweenDeg(o, d) > 2;
    if (far) lights.push_back(d);
  }
  return lights;
}

// A dome-like set: 3 rings at 20, 40, 60 deg with 6 lights each, plus the zenith.
std::vector<Eigen::Vector3d> DomeLights() {
  std::vector<Eigen::Vector3d> lights{{0, 0, 1}};
  for (double theta : {20.0, 40.0, 60.0})
    for (int k = 0; k < 6; ++k) lights.push_back(DirectionFromAnglesDeg(theta, 60.0 * k + theta));
  return lights;
}

TEST(Ptm, RgbFitRecoversKnownCoefficients) {
  std::mt19937 rng(testing::SeedFromTestName());
  std::uniform_real_distribution<double> coef(-0.5, 0.5);
  const int w = 7, h = 5;
  const auto lights = RandomLights(rng, 12);
  std::vector<std::vector<double>> truth(w * h * 3, std::vector<double>(6));
  for (auto& t : truth)
    for (double& v : t) v = coef(rng);
  std::vector<Image> images;
  for (const auto& l : lights) {
    Image im(w, h, 3);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (int c = 0; c < 3; ++c)
          im.at(x, y, c) = float(Eval(truth[(y * w + x) * 3 + c].data(), l));
    images.push_back(im);
  }
  PtmFitOptions options;
  options.format = PtmFormat::kRgb;
  PtmFitReport report;
  const StatusOr<Ptm> ptm = FitPtm(images, lights, options, &report);
  ASSERT_TRUE(ptm.ok()) << ptm.status().message();
  ASSERT_TRUE(ptm->IsConsistent());
  EXPECT_EQ(ptm->coefficients.channels(), 18);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c)
        for (int k = 0; k < 6; ++k)
          EXPECT_NEAR(ptm->coefficients.at(x, y, c * 6 + k), truth[(y * w + x) * 3 + c][k], 2e-5)
              << x << "," << y << " channel " << c << " a" << k;
  EXPECT_LT(report.rms_residual, 1e-5);
  EXPECT_EQ(report.num_lights, 12);
  EXPECT_GT(report.light_matrix_condition, 1.0);
}

TEST(Ptm, LrgbFitRecoversLuminanceTimesColour) {
  std::mt19937 rng(testing::SeedFromTestName());
  std::uniform_real_distribution<double> small(-0.15, 0.15), colour(0.05, 0.9);
  const int w = 6, h = 4;
  const auto lights = DomeLights();
  std::vector<std::array<double, 6>> lum(w * h);
  std::vector<std::array<double, 3>> rgb(w * h);
  for (int p = 0; p < w * h; ++p) {
    for (int k = 0; k < 5; ++k) lum[p][k] = small(rng);
    lum[p][5] = 0.7;
    for (double& c : rgb[p]) c = colour(rng);
  }
  std::vector<Image> images;
  for (const auto& l : lights) {
    Image im(w, h, 3);
    for (int p = 0; p < w * h; ++p)
      for (int c = 0; c < 3; ++c) im.data()[p * 3 + c] = float(Eval(lum[p].data(), l) * rgb[p][c]);
    images.push_back(im);
  }
  PtmFitReport report;
  const StatusOr<Ptm> ptm = FitPtm(images, lights, {}, &report);
  ASSERT_TRUE(ptm.ok()) << ptm.status().message();
  ASSERT_TRUE(ptm->IsConsistent());
  EXPECT_LT(report.rms_residual, 1e-5);
  for (int p = 0; p < w * h; ++p) {
    const int x = p % w, y = p / w;
    // The split between polynomial and colour is a per-pixel scale: compare the products.
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < 6; ++k)
        EXPECT_NEAR(ptm->coefficients.at(x, y, k) * ptm->rgb.at(x, y, c), lum[p][k] * rgb[p][c],
                    2e-5);
    // Normalisation: the polynomial peaks near 1 over the measured lights; the colour fits in [0,
    // 1].
    double peak = 0;
    double a[6];
    for (int k = 0; k < 6; ++k) a[k] = ptm->coefficients.at(x, y, k);
    for (const auto& l : lights) peak = std::max(peak, Eval(a, l));
    EXPECT_NEAR(peak, 1.0, 1e-4);
    for (int c = 0; c < 3; ++c) EXPECT_LE(ptm->rgb.at(x, y, c), 1.0f);
  }
  // Relighting at a held-out light reproduces the truth.
  const Eigen::Vector3d held_out = DirectionFromAnglesDeg(33, 101);
  const Image relit = RelightPtm(*ptm, held_out, /*clamp=*/false);
  for (int p = 0; p < w * h; ++p)
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(relit.data()[p * 3 + c], Eval(lum[p].data(), held_out) * rgb[p][c], 1e-5);
}

TEST(Ptm, ResultIndependentOfThreadCountAndAcceptsGreyAndAlpha) {
  std::mt19937 rng(testing::SeedFromTestName());
  std::uniform_real_distribution<float> value(0, 1);
  const auto lights = RandomLights(rng, 9);
  std::vector<Image> grey, rgba;
  for (size_t i = 0; i < lights.size(); ++i) {
    Image g(13, 11, 1), a(13, 11, 4);
    for (size_t p = 0; p < g.pixel_count(); ++p) {
      g.data()[p] = value(rng);
      for (int c = 0; c < 3; ++c) a.data()[p * 4 + c] = g.data()[p];
      a.data()[p * 4 + 3] = value(rng);  // alpha: ignored
    }
    grey.push_back(g);
    rgba.push_back(a);
  }
  for (PtmFormat format : {PtmFormat::kLrgb, PtmFormat::kRgb}) {
    PtmFitOptions one, all;
    one.format = all.format = format;
    one.num_threads = 1;
    const StatusOr<Ptm> a = FitPtm(grey, lights, one), b = FitPtm(grey, lights, all),
                        c = FitPtm(rgba, lights, all);
    ASSERT_TRUE(a.ok() && b.ok() && c.ok());
    EXPECT_TRUE(a->coefficients == b->coefficients);
    EXPECT_TRUE(a->rgb == b->rgb);
    EXPECT_TRUE(a->coefficients == c->coefficients);
  }
}

TEST(Ptm, LrgbColourStaysWithinEightBitsAndResidualMatchesRelighting) {
  std::mt19937 rng(testing::SeedFromTestName());
  std::uniform_real_distribution<float> value(0, 1);
  const auto lights = DomeLights();
  const int w = 8, h = 5;
  std::vector<Image> images;
  for (size_t i = 0; i < lights.size(); ++i) {
    Image im(w, h, 3);
    for (size_t p = 0; p < im.pixel_count(); ++p) {
      im.data()[p * 3 + 0] = 1.0f;  // saturated red: its least-squares colour exceeds 1
      im.data()[p * 3 + 1] = value(rng);
      im.data()[p * 3 + 2] = 0.1f * value(rng);
    }
    images.push_back(im);
  }
  PtmFitReport report;
  const StatusOr<Ptm> ptm = FitPtm(images, lights, {}, &report);
  ASSERT_TRUE(ptm.ok()) << ptm.status().message();
  for (size_t p = 0; p < ptm->rgb.pixel_count(); ++p) {
    const float* rgb = ptm->rgb.data() + p * 3;
    EXPECT_FLOAT_EQ(std::max({rgb[0], rgb[1], rgb[2]}), 1.0f);
  }
  // The reported residual is that of the stored (rescaled) polynomial and colour.
  double sse = 0;
  for (size_t i = 0; i < lights.size(); ++i) {
    const Image relit = RelightPtm(*ptm, lights[i], /*clamp=*/false);
    for (size_t k = 0; k < relit.size(); ++k)
      sse += std::pow(relit.data()[k] - images[i].data()[k], 2);
  }
  EXPECT_NEAR(report.rms_residual, std::sqrt(sse / double(w * h * 3 * lights.size())), 1e-5);
  EXPECT_GT(report.rms_residual, 0.01);
  // Without the residual the coefficients are the same and the report says so.
  PtmFitOptions fast;
  fast.compute_residual = false;
  PtmFitReport fast_report;
  const StatusOr<Ptm> again = FitPtm(images, lights, fast, &fast_report);
  ASSERT_TRUE(again.ok());
  EXPECT_TRUE(again->coefficients == ptm->coefficients);
  EXPECT_EQ(fast_report.rms_residual, -1);
  EXPECT_NE(fast_report.Brief().find("rms residual not computed"), std::string::npos);
  EXPECT_NE(report.Brief().find("19 lights"), std::string::npos) << report.Brief();
}

// 8-bit photos of a smooth lit surface with a per-pixel colour and some sensor noise: values
// across the whole 0..255 range, including clipped ones.
std::vector<ImageU8> EightBitImages(std::mt19937& rng, const std::vector<Eigen::Vector3d>& lights,
                                    int w, int h, int channels) {
  std::uniform_real_distribution<double> coef(-0.3, 0.3), colour(0.1, 1.2), noise(-3, 3);
  std::vector<std::array<double, 6>> poly(size_t(w) * h);
  std::vector<std::array<double, 4>> rgb(size_t(w) * h);
  for (size_t p = 0; p < poly.size(); ++p) {
    for (int k = 0; k < 5; ++k) poly[p][k] = coef(rng);
    poly[p][5] = 0.6;
    for (double& c : rgb[p]) c = colour(rng);
  }
  std::vector<ImageU8> images;
  for (const auto& l : lights) {
    ImageU8 im(w, h, channels);
    for (size_t p = 0; p < poly.size(); ++p)
      for (int c = 0; c < channels; ++c) {
        const double v = 255 * Eval(poly[p].data(), l) * rgb[p][c] + noise(rng);
        im.data()[p * channels + c] = uint8_t(std::clamp(std::lround(v), 0L, 255L));
      }
    images.push_back(std::move(im));
  }
  return images;
}

void ExpectImagesNear(const Image& a, const Image& b, float tolerance, const char* what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  float worst = 0;
  for (size_t i = 0; i < a.size(); ++i) worst = std::max(worst, std::abs(a.data()[i] - b.data()[i]));
  EXPECT_LE(worst, tolerance) << what;
}

TEST(Ptm, EightBitFitAgreesWithFloatFitOfTheSameValues) {
  std::mt19937 rng(testing::SeedFromTestName());
  const auto lights = RandomLights(rng, 17);
  // 150 px: two whole blocks of the streaming fit and a partial one.
  const int w = 150, h = 6;
  for (int channels : {3, 1, 4}) {
    const std::vector<ImageU8> u8 = EightBitImages(rng, lights, w, h, channels);
    std::vector<Image> as_float;
    for (const ImageU8& im : u8) as_float.push_back(ImageU8ToFloat(im));
    for (PtmFormat format : {PtmFormat::kRgb, PtmFormat::kLrgb}) {
      PtmFitOptions options;
      options.format = format;
      PtmFitReport r8, rf;
      const StatusOr<Ptm> p8 = FitPtm(u8, lights, options, &r8);
      const StatusOr<Ptm> pf = FitPtm(as_float, lights, options, &rf);
      ASSERT_TRUE(p8.ok() && pf.ok()) << p8.status().message() << pf.status().message();
      ASSERT_TRUE(p8->IsConsistent());
      // Same values, same kernel: equal up to float round-off.
      ExpectImagesNear(p8->coefficients, pf->coefficients, 1e-6f, "coefficients");
      if (format == PtmFormat::kLrgb) ExpectImagesNear(p8->rgb, pf->rgb, 1e-6f, "rgb");
      EXPECT_NEAR(r8.rms_residual, rf.rms_residual, 1e-6 * rf.rms_residual);
      EXPECT_GT(r8.rms_residual, 0.5 / 255);  // the noise is there
      EXPECT_EQ(r8.width, w);
      EXPECT_EQ(r8.num_lights, 17);
      // Independent of the thread count.
      PtmFitOptions one = options;
      one.num_threads = 1;
      const StatusOr<Ptm> single = FitPtm(u8, lights, one);
      ASSERT_TRUE(single.ok());
      EXPECT_TRUE(single->coefficients == p8->coefficients);
      EXPECT_TRUE(single->rgb == p8->rgb);
    }
    // The RGB coefficients are the least-squares solution, checked in double precision.
    PtmFitOptions rgb_options;
    rgb_options.format = PtmFormat::kRgb;
    const StatusOr<Ptm> p8 = FitPtm(u8, lights, rgb_options);
    ASSERT_TRUE(p8.ok());
    Eigen::MatrixXd a(lights.size(), 6);
    for (size_t i = 0; i < lights.size(); ++i) a.row(i) = PtmBasis(lights[i]);
    for (int x : {0, 63, 64, 149}) {
      const int y = x % h;
      for (int c = 0; c < 3; ++c) {
        Eigen::VectorXd b(lights.size());
        for (size_t i = 0; i < lights.size(); ++i)
          b(i) = u8[i].at(x, y, channels == 1 ? 0 : c) / 255.0;
        const Eigen::VectorXd truth = a.colPivHouseholderQr().solve(b);
        for (int k = 0; k < 6; ++k)
          EXPECT_NEAR(p8->coefficients.at(x, y, c * 6 + k), truth(k), 2e-5)
              << x << "," << y << " channel " << c << " a" << k;
      }
    }
  }
}

TEST(Ptm, EightBitFitChecksItsInputs) {
  const auto lights = DomeLights();
  std::vector<ImageU8> images(lights.size(), ImageU8(4, 3, 3));
  images[4] = ImageU8(5, 3, 3);
  const StatusOr<Ptm> mismatched = FitPtm(images, lights);
  ASSERT_FALSE(mismatched.ok());
  EXPECT_NE(mismatched.status().message().find("image 5 is 5x3x3 but image 1 is 4x3x3"),
            std::string::npos)
      << mismatched.status().message();
  images.pop_back();
  const StatusOr<Ptm> unpaired = FitPtm(images, lights);
  ASSERT_FALSE(unpaired.ok());
  EXPECT_NE(unpaired.status().message().find("18 images but 19 light directions"),
            std::string::npos);
}

TEST(Ptm, FormatNamesRoundTrip) {
  for (PtmFormat f : {PtmFormat::kLrgb, PtmFormat::kRgb}) {
    PtmFormat back;
    ASSERT_TRUE(StringToPtmFormat(PtmFormatToString(f), &back));
    EXPECT_EQ(back, f);
  }
  PtmFormat f;
  EXPECT_TRUE(StringToPtmFormat("LRGB", &f));
  EXPECT_FALSE(StringToPtmFormat("hsh", &f));
  PtmFitOptions options;
  EXPECT_TRUE(options.Check());
  options.max_condition = 0;
  EXPECT_FALSE(options.Check());
  options = {};
  options.num_threads = 0;
  EXPECT_FALSE(options.Check());
}

std::vector<Image> FlatImages(int n, int w = 4, int h = 3) {
  return std::vector<Image>(n, Image(w, h, 3, 0.5f));
}

void ExpectError(const StatusOr<Ptm>& result, const std::string& fragment) {
  ASSERT_FALSE(result.ok());
  EXPECT_NE(result.status().message().find(fragment), std::string::npos)
      << result.status().message();
}

TEST(Ptm, RejectsFewerThanSixLights) {
  auto lights = DomeLights();
  lights.resize(5);
  ExpectError(FitPtm(FlatImages(5), lights),
              "at least 6 light directions (6 coefficients per pixel), got 5");
}

TEST(Ptm, AcceptsNearDuplicateLightsWithAWarning) {
  // A repeated shot (0.23 deg apart, and one exactly repeated) is normal in a real capture.
  auto lights = DomeLights();
  lights.push_back(lights[3]);
  lights[7] = DirectionFromAnglesDeg(40.23, 60.0 * 1 + 40);  // light 8 is 0.23 deg from light 9
  lights[8] = DirectionFromAnglesDeg(40, 60.0 * 1 + 40);
  PtmLightCheck check;
  ASSERT_TRUE(ValidatePtmLights(lights, {}, &check).ok());
  ASSERT_EQ(check.warnings.size(), 2u);
  EXPECT_NE(check.warnings[0].find("lights 4 and 20 of 20 are 0 deg apart"), std::string::npos) << check.warnings[0];
  EXPECT_NE(check.warnings[1].find("lights 8 and 9 of 20 are 0.23 deg apart"), std::string::npos) << check.warnings[1];
  PtmFitReport report;
  ASSERT_TRUE(FitPtm(FlatImages(int(lights.size())), lights, {}, &report).ok());
  EXPECT_EQ(report.warnings, check.warnings);
}

TEST(Ptm, RejectsCollinearLights) {
  std::vector<Eigen::Vector3d> lights;
  for (int k = 0; k < 8; ++k)
    lights.push_back(DirectionFromAnglesDeg(-70 + 20 * k, 30));  // one plane
  ExpectError(FitPtm(FlatImages(8), lights), "collinear");
}

TEST(Ptm, RejectsLightsAllAtOneElevation) {
  std::vector<Eigen::Vector3d> lights;
  for (int k = 0; k < 12; ++k) lights.push_back(DirectionFromAnglesDeg(45, 30.0 * k));
  ExpectError(FitPtm(FlatImages(12), lights), "numerical rank 5 of 6");
  ExpectError(FitPtm(FlatImages(12), lights), "all lights lie at elevations 45.0 to 45.0 deg: add lights at other elevations");
}

TEST(Ptm, RejectsANearlySingularRingWrittenWithFourDecimals) {
  // One ring at 30 deg elevation as a .lp file stores it: rounding to 4 decimals breaks the exact
  // rank deficiency (the raw light matrix's reciprocal condition is 4e-6), not the ill-conditioning.
  std::vector<Eigen::Vector3d> lights;
  for (int k = 0; k < 36; ++k) {
    Eigen::Vector3d d = DirectionFromAnglesDeg(60, 10.0 * k);
    for (int i = 0; i < 3; ++i) d[i] = std::round(d[i] * 1e4) / 1e4;
    lights.push_back(d);
  }
  ExpectError(FitPtm(FlatImages(36), lights), "too poorly spread");
  ExpectError(FitPtm(FlatImages(36), lights), "add lights at other elevations");
  // One light at the zenith makes the same ring well conditioned.
  lights.push_back({0, 0, 1});
  PtmLightCheck check;
  ASSERT_TRUE(ValidatePtmLights(lights, {}, &check).ok());
  EXPECT_LT(check.condition, 100);
  EXPECT_TRUE(check.warnings.empty());
}

TEST(Ptm, NamesTheMissingElevationsAndAzimuths) {
  // Part of one ring: on the conic lu^2 + lv^2 = const, and a quarter of the azimuths.
  std::vector<Eigen::Vector3d> lights;
  for (double phi = 0; phi <= 90.01; phi += 10) lights.push_back(DirectionFromAnglesDeg(50, phi));
  const Status st = ValidatePtmLights(lights, {});
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.message().find("all lights lie at elevations 40.0 to 40.0 deg"), std::string::npos) << st.message();
  EXPECT_NE(st.message().find("no light between azimuths 90 and 0 deg: add lights there"), std::string::npos)
      << st.message();
}

TEST(Ptm, RejectsInvalidDirectionAndMismatchedInputs) {
  auto lights = DomeLights();
  const int n = int(lights.size());
  lights[2] = Eigen::Vector3d::Zero();
  ExpectError(FitPtm(FlatImages(n), lights), "light 3 of 19");
  lights = DomeLights();
  ExpectError(FitPtm(FlatImages(n - 1), lights), "18 images but 19 light directions");
  auto images = FlatImages(n);
  images[5] = Image(5, 3, 3);
  ExpectError(FitPtm(images, lights), "image 6 is 5x3x3 but image 1 is 4x3x3");
  images = FlatImages(n);
  images[9] = Image(4, 3, 1);
  ExpectError(FitPtm(images, lights), "same size and channel count");
  images = std::vector<Image>(n, Image(4, 3, 2));
  ExpectError(FitPtm(images, lights), "1, 3 or 4 channels");
}

// f(x) = 0.5 x^T H x - (H p)^T x + c has its maximum at p when H is negative definite.
void PolynomialWithMaximum(const Eigen::Matrix2d& hess, const Eigen::Vector2d& p, double c,
                           double a[6]) {
  const Eigen::Vector2d g = -hess * p;
  a[0] = 0.5 * hess(0, 0);
  a[1] = 0.5 * hess(1, 1);
  a[2] = hess(0, 1);
  a[3] = g(0);
  a[4] = g(1);
  a[5] = c;
}

TEST(Ptm, MaximumDirectionInteriorAndOnTheRim) {
  double a[6];
  Eigen::Matrix2d hess;
  hess << -1.2, 0.3, 0.3, -0.8;
  PolynomialWithMaximum(hess, {0.3, -0.4}, 0.9, a);
  const Eigen::Vector3d n = PtmMaximumDirection(a);
  EXPECT_NEAR(n.x(), 0.3, 1e-12);
  EXPECT_NEAR(n.y(), -0.4, 1e-12);
  EXPECT_NEAR(n.z(), std::sqrt(1 - 0.25), 1e-12);
  // A linear ramp peaks on the rim, in the direction of its gradient.
  const double ramp[6] = {0, 0, 0, 0.6, 0.8, 0.2};
  const Eigen::Vector3d r = PtmMaximumDirection(ramp);
  EXPECT_NEAR(r.x(), 0.6, 1e-6);
  EXPECT_NEAR(r.y(), 0.8, 1e-6);
  EXPECT_NEAR(r.z(), 0.0, 1e-12);
  // Concave but peaking outside the disk: also on the rim.
  PolynomialWithMaximum(hess, {2.0, 0.0}, 0.5, a);
  EXPECT_NEAR(PtmMaximumDirection(a).norm(), 1.0, 1e-9);
  EXPECT_NEAR(PtmMaximumDirection(a).z(), 0.0, 1e-12);
  // Flat: straight up.
  const double flat[6] = {0, 0, 0, 0, 0, 0.4};
  EXPECT_EQ(PtmMaximumDirection(flat), Eigen::Vector3d(0, 0, 1));
}

TEST(Ptm, NormalsAndAlbedoOfKnownPolynomials) {
  std::mt19937 rng(testing::SeedFromTestName());
  std::uniform_real_distribution<double> offset(-0.5, 0.5), colour(0.1, 0.9);
  const int w = 5, h = 4;
  const auto lights = DomeLights();
  std::vector<Eigen::Vector2d> peaks(w * h);
  std::vector<Eigen::Vector3d> colours(w * h);
  std::vector<double> peak_values(w * h);
  std::vector<Image> images(lights.size(), Image(w, h, 3));
  Eigen::Matrix2d hess;
  hess << -0.9, 0.2, 0.2, -1.1;
  for (int p = 0; p < w * h; ++p) {
    peaks[p] = {offset(rng), offset(rng)};
    colours[p] = {colour(rng), colour(rng), colour(rng)};
    double a[6];
    PolynomialWithMaximum(hess, peaks[p], 0.6, a);
    peak_values[p] =
        Eval(a, Eigen::Vector3d(peaks[p].x(), peaks[p].y(), std::sqrt(1 - peaks[p].squaredNorm())));
    for (size_t i = 0; i < lights.size(); ++i)
      for (int c = 0; c < 3; ++c)
        images[i].data()[p * 3 + c] = float(Eval(a, lights[i]) * colours[p](c));
  }
  for (PtmFormat format : {PtmFormat::kLrgb, PtmFormat::kRgb}) {
    PtmFitOptions options;
    options.format = format;
    const StatusOr<Ptm> ptm = FitPtm(images, lights, options);
    ASSERT_TRUE(ptm.ok()) << ptm.status().message();
    const PtmNormalsAlbedo na = PtmNormalsAndAlbedo(*ptm);
    for (int p = 0; p < w * h; ++p) {
      const float* n = na.normals.data() + p * 3;
      EXPECT_NEAR(n[0], peaks[p].x(), 1e-4);
      EXPECT_NEAR(n[1], peaks[p].y(), 1e-4);
      EXPECT_NEAR(Eigen::Vector3d(n[0], n[1], n[2]).norm(), 1.0, 1e-5);
      // The albedo is the colour the PTM predicts at its maximum.
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(na.albedo.data()[p * 3 + c], peak_values[p] * colours[p](c), 1e-4);
    }
  }
}

TEST(Ptm, LambertianNormalsAreClose) {
  std::mt19937 rng(testing::SeedFromTestName());
  std::uniform_real_distribution<double> tilt(0, 25), azimuth(0, 360), albedo(0.2, 0.8);
  const int w = 16, h = 16;
  std::vector<Eigen::Vector3d> lights;
  for (double theta : {15.0, 30.0, 45.0, 60.0})
    for (int k = 0; k < 8; ++k) lights.push_back(DirectionFromAnglesDeg(theta, 45.0 * k + theta));
  std::vector<Eigen::Vector3d> normals(w * h);
  std::vector<double> rho(w * h);
  std::vector<Image> images(lights.size(), Image(w, h, 1));
  for (int p = 0; p < w * h; ++p) {
    normals[p] = DirectionFromAnglesDeg(tilt(rng), azimuth(rng));
    rho[p] = albedo(rng);
    for (size_t i = 0; i < lights.size(); ++i)
      images[i].data()[p] = float(rho[p] * std::max(0.0, normals[p].dot(lights[i])));
  }
  const StatusOr<Ptm> ptm = FitPtm(images, lights);
  ASSERT_TRUE(ptm.ok()) << ptm.status().message();
  const PtmNormalsAlbedo na = PtmNormalsAndAlbedo(*ptm);
  double worst_deg = 0, worst_albedo = 0;
  for (int p = 0; p < w * h; ++p) {
    const float* n = na.normals.data() + p * 3;
    worst_deg = std::max(worst_deg, AngleBetweenDeg(normals[p], Eigen::Vector3d(n[0], n[1], n[2])));
    worst_albedo = std::max(worst_albedo, std::abs(na.albedo.data()[p * 3] / rho[p] - 1));
  }
  // A biquadratic only approximates the cosine lobe: the normals are close, not exact.
  EXPECT_LT(worst_deg, 7.0);  // measured 4.95 deg with this seed
  EXPECT_LT(worst_albedo, 0.05);
  RecordProperty("worst_normal_error_deg", std::to_string(worst_deg));
  RecordProperty("worst_albedo_rel_error", std::to_string(worst_albedo));
}

TEST(Ptm, RelightClampsLikeTheViewers) {
  Ptm ptm;
  ptm.format = PtmFormat::kRgb;
  ptm.coefficients = Image(1, 1, 18);
  for (int c = 0; c < 3; ++c)
    ptm.coefficients.at(0, 0, c * 6 + 5) = 0.5f * (c - 1) + 0.9f;  // 0.4, 0.9, 1.4
  const Image clamped = RelightPtm(ptm, {0, 0, 1});
  EXPECT_FLOAT_EQ(clamped.at(0, 0, 0), 0.4f);
  EXPECT_FLOAT_EQ(clamped.at(0, 0, 1), 0.9f);
  EXPECT_FLOAT_EQ(clamped.at(0, 0, 2), 1.0f);
  EXPECT_FLOAT_EQ(RelightPtm(ptm, {0, 0, 1}, false).at(0, 0, 2), 1.4f);
}

// A flash 0.3 m above a 64 mm patch: each texel sees each light from its own direction. Data
// made from known per-texel polynomials evaluated at those directions is recovered exactly by the
// per-pixel fit, and not by the shared fit that uses the patch centre's directions.
TEST(Ptm, PerPixelLightsRecoverKnownCoefficientsUnderAPointLight) {
  std::mt19937 rng(testing::SeedFromTestName());
  std::uniform_real_distribution<double> coef(-0.5, 0.5);
  const int size = 8;
  const double patch_m = 0.064;
  std::vector<Eigen::Vector3d> lights_m;
  for (const auto& d : RandomLights(rng, 14)) lights_m.push_back(0.3 * d);
  const PixelLightFn dir = PointLightDirections(lights_m, size, patch_m);
  std::vector<std::vector<double>> truth(size * size * 3, std::vector<double>(6));
  for (auto& t : truth)
    for (double& v : t) v = coef(rng);
  std::vector<Image> images;
  for (int i = 0; i < int(lights_m.size()); ++i) {
    Image im(size, size, 3);
    for (int y = 0; y < size; ++y)
      for (int x = 0; x < size; ++x)
        for (int c = 0; c < 3; ++c) im.at(x, y, c) = float(Eval(truth[(y * size + x) * 3 + c].data(), dir(i, x, y)));
    images.push_back(im);
  }
  PtmFitOptions options;
  options.format = PtmFormat::kRgb;
  PtmFitReport per_pixel_report, shared_report;
  int degenerate = -1;
  const StatusOr<Ptm> ptm = FitPtmPerPixelLights(images, dir, options, &per_pixel_report, &degenerate);
  ASSERT_TRUE(ptm.ok()) << ptm.status().message();
  EXPECT_EQ(degenerate, 0);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x)
      for (int c = 0; c < 3; ++c)
        for (int k = 0; k < 6; ++k)
          EXPECT_NEAR(ptm->coefficients.at(x, y, c * 6 + k), truth[(y * size + x) * 3 + c][k], 1e-4);
  EXPECT_LT(per_pixel_report.rms_residual, 1e-5);
  std::vector<Eigen::Vector3d> centre;
  for (const auto& l : lights_m) centre.push_back(l.normalized());
  ASSERT_TRUE(FitPtm(images, centre, options, &shared_report).ok());
  EXPECT_GT(shared_report.rms_residual, 100 * per_pixel_report.rms_residual);
}

TEST(Ptm, PerPixelFitEqualsTheSharedFitForADistantLight) {
  std::mt19937 rng(testing::SeedFromTestName());
  std::uniform_real_distribution<float> value(0.05f, 0.9f);
  const auto lights = DomeLights();
  std::vector<Image> images;
  for (size_t i = 0; i < lights.size(); ++i) {
    Image im(6, 4, 3);
    for (size_t k = 0; k < im.size(); ++k) im.data()[k] = value(rng);
    images.push_back(im);
  }
  for (const PtmFormat format : {PtmFormat::kRgb, PtmFormat::kLrgb}) {
    PtmFitOptions options;
    options.format = format;
    const auto shared = FitPtm(images, lights, options);
    const auto per_pixel = FitPtmPerPixelLights(images, [&](int i, int, int) { return lights[i]; }, options);
    ASSERT_TRUE(shared.ok() && per_pixel.ok());
    for (size_t k = 0; k < shared->coefficients.size(); ++k)
      EXPECT_NEAR(shared->coefficients.data()[k], per_pixel->coefficients.data()[k], 2e-4) << PtmFormatToString(format);
    for (size_t k = 0; k < shared->rgb.size(); ++k)
      EXPECT_NEAR(shared->rgb.data()[k], per_pixel->rgb.data()[k], 2e-4);
  }
}

TEST(Ptm, ThePerPixelResidualMapAddsUpToTheReportAndPointsAtABadPixel) {
  std::mt19937 rng(testing::SeedFromTestName());
  std::normal_distribution<float> noise(0.0f, 0.01f);
  const auto lights = DomeLights();
  std::vector<Image> images;
  for (size_t i = 0; i < lights.size(); ++i) {
    Image im(8, 6, 3);
    for (int y = 0; y < im.height(); ++y)
      for (int x = 0; x < im.width(); ++x)
        for (int c = 0; c < 3; ++c) im.at(x, y, c) = float(0.3 + 0.5 * lights[i].z()) + noise(rng);
    images.push_back(im);
  }
  images[3].at(5, 2, 1) += 0.6f;  // one bad observation
  for (const PtmFormat format : {PtmFormat::kRgb, PtmFormat::kLrgb}) {
    PtmFitOptions options;
    options.format = format;
    PtmFitReport report;
    Image residual;
    ASSERT_TRUE(FitPtmPerPixelLights(images, [&](int i, int, int) { return lights[i]; }, options, &report, nullptr, &residual).ok());
    double sum = 0;
    int worst = 0;
    for (size_t k = 0; k < residual.size(); ++k) {
      sum += double(residual.data()[k]) * residual.data()[k];
      if (residual.data()[k] > residual.data()[worst]) worst = int(k);
    }
    EXPECT_NEAR(std::sqrt(sum / residual.size()), report.rms_residual, 1e-6 * (1 + report.rms_residual));
    EXPECT_EQ(worst, 2 * 8 + 5) << PtmFormatToString(format);
  }
}

}  // namespace
}  // namespace mesocap
