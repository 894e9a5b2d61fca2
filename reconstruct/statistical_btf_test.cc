#include "reconstruct/statistical_btf.h"

#include <cmath>
#include <cstdio>
#include <random>
#include <span>

#include <gtest/gtest.h>

#include "core/directions.h"
#include "reconstruct/btf_evaluation.h"
#include "reconstruct/rig_coverage_testing.h"
#include "tests/testing.h"

namespace mesocap {
namespace {

// A synthetic BTF with a closed form: the top view under light l is a fixed random texture
// shaded by a light-dependent gain; a view at incidence theta sees a monotone tone curve of
// it, value^(1 + theta/60) * (1 + theta/90). Pixel histogram matching of the base texture to a
// measured view's statistics must then give that view's slice back (ranks are preserved).
struct SyntheticBtf {
  Image texture;
  explicit SyntheticBtf(int size, uint32_t seed) : texture(size, size, 1) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.1f, 1.0f);
    for (size_t i = 0; i < texture.size(); ++i) texture.data()[i] = u(rng);
  }
  Image Slice(const Eigen::Vector3d& light, const Eigen::Vector3d& view) const {
    const double gain = 0.2 + light.normalized().z();
    const double theta = AnglesDegFromDirection(view).x();
    Image out = texture;
    for (size_t i = 0; i < out.size(); ++i)
      out.data()[i] = float(std::pow(gain * texture.data()[i], 1 + theta / 60) * (1 + theta / 90));
    return out;
  }
};

struct Fixture {
  std::vector<Eigen::Vector3d> lights = BonnDirections();
  std::vector<Eigen::Vector3d> views = {Eigen::Vector3d::UnitZ(), DirectionFromAnglesDeg(30, 0), DirectionFromAnglesDeg(30, 120),
                                        DirectionFromAnglesDeg(30, 240), DirectionFromAnglesDeg(60, 60),
                                        DirectionFromAnglesDeg(60, 180), DirectionFromAnglesDeg(60, 300)};
};

StatusOr<StatisticalBtf> Build(const SyntheticBtf& btf, const Fixture& f, const StatisticalBtfOptions& options) {
  std::vector<MeasuredView> measured;
  std::vector<Image> top;
  for (const auto& view : f.views) {
    std::vector<Image> slices;
    for (const auto& light : f.lights) slices.push_back(btf.Slice(light, view));
    if (view.z() > 0.999) top = slices;
    measured.push_back(MeasureView(view, f.lights, slices, options));
  }
  return StatisticalBtf::Create(top, f.lights, std::move(measured), options);
}

double RelativeRms(const Image& a, const Image& b) {
  double d = 0, n = 0;
  for (size_t i = 0; i < a.size(); ++i) d += std::pow(a.data()[i] - b.data()[i], 2), n += std::pow(b.data()[i], 2);
  return std::sqrt(d / n);
}

TEST(StatisticalBtf, PixelMatchingRecoversAMeasuredViewsToneCurve) {
  SyntheticBtf truth(64, testing::SeedFromTestName());
  Fixture f;
  StatisticalBtfOptions options;
  options.match_subbands = false;
  auto btf = Build(truth, f, options);
  ASSERT_TRUE(btf.ok()) << btf.status().message();
  for (int v : {1, 4, 6}) {
    const Eigen::Vector3d light = f.lights[23];
    const Image got = btf->Reconstruct(light, f.views[v]);
    EXPECT_LT(RelativeRms(got, truth.Slice(light, f.views[v])), 0.01) << "view " << v;
  }
}

TEST(StatisticalBtf, FullMatchingStaysCloseAndBaseInterpolatesTopSlices) {
  SyntheticBtf truth(64, testing::SeedFromTestName());
  Fixture f;
  auto btf = Build(truth, f, {});
  ASSERT_TRUE(btf.ok()) << btf.status().message();
  // A measured top-view light: the base is that slice exactly.
  EXPECT_LT(RelativeRms(btf->BaseTexture(f.lights[40]), truth.Slice(f.lights[40], f.views[0])), 1e-6);
  // Between rings and lights the reconstruction follows the tone curve, subbands included.
  const Eigen::Vector3d light = DirectionFromAnglesDeg(37, 200), view = DirectionFromAnglesDeg(45, 90);
  EXPECT_LT(RelativeRms(btf->Reconstruct(light, view), truth.Slice(light, view)), 0.08);
  EXPECT_GT(RelativeRms(btf->BaseTexture(light), truth.Slice(light, view)), 0.15);  // the base alone is off
}

// A top view whose texture's radiance falls as cos(theta_i)^exponent, measured under `lights`:
// the relative RMS error of the base texture at `query` against the true slice there.
double FalloffBaseError(const std::vector<Eigen::Vector3d>& lights, double exponent, const Eigen::Vector3d& query,
                        const StatisticalBtfOptions& options) {
  const SyntheticBtf texture(32, testing::SeedFromTestName());
  auto slice = [&](const Eigen::Vector3d& l) {
    Image out = texture.texture;
    for (size_t i = 0; i < out.size(); ++i) out.data()[i] *= float(std::pow(l.z(), exponent));
    return out;
  };
  std::vector<Image> top;
  for (const auto& l : lights) top.push_back(slice(l));
  auto btf = StatisticalBtf::Create(top, lights, {MeasureView(Eigen::Vector3d::UnitZ(), lights, top, options)}, options);
  EXPECT_TRUE(btf.ok()) << btf.status().message();
  return btf.ok() ? RelativeRms(btf->BaseTexture(query), slice(query)) : 1.0;
}

std::vector<Eigen::Vector3d> HeadOnAndRingLights() {
  std::vector<Eigen::Vector3d> lights = {Eigen::Vector3d::UnitZ()};
  for (int k = 0; k < 5; ++k) lights.push_back(DirectionFromAnglesDeg(70, 72.0 * k));
  return lights;
}

// A Lambertian-like BTF, texture x cos(theta_i), measured under a few lights far apart: blending
// the cosine-normalised slices gives any light's slice exactly; blending values as measured
// (the paper's) does not.
TEST(StatisticalBtf, CosineWeightedLightsInterpolateALambertianFalloffExactly) {
  const Eigen::Vector3d query = DirectionFromAnglesDeg(40, 100);
  StatisticalBtfOptions options;
  EXPECT_LT(FalloffBaseError(HeadOnAndRingLights(), 1.0, query, options), 1e-5);
  options.cosine_weighted_lights = false;
  EXPECT_GT(FalloffBaseError(HeadOnAndRingLights(), 1.0, query, options), 0.05);
}

// A rough material's radiance may fall more slowly than the cosine: texture x cos(theta_i)^0.6.
// The exponent fitted to the top view's means makes the blend exact again; plain cosine ratios
// (fit_light_falloff = false) overshoot the fall-off between lights far apart in elevation.
TEST(StatisticalBtf, TheFittedLightFalloffInterpolatesASlowerThanCosineFalloffExactly) {
  std::vector<Eigen::Vector3d> lights = HeadOnAndRingLights();
  for (int k = 0; k < 4; ++k) lights.push_back(DirectionFromAnglesDeg(40, 90.0 * k + 20));
  const Eigen::Vector3d query = DirectionFromAnglesDeg(55, 100);
  StatisticalBtfOptions options;
  EXPECT_LT(FalloffBaseError(lights, 0.6, query, options), 1e-4);
  options.fit_light_falloff = false;
  EXPECT_GT(FalloffBaseError(lights, 0.6, query, options), 0.02);
}

// The synthetic BTF in colour: each texel's value times a tint (orange unless given).
constexpr float kOrange[3] = {1.0f, 0.6f, 0.3f};
Image Tinted(const Image& grey, const float (&tint)[3] = kOrange) {
  Image out(grey.width(), grey.height(), 3);
  for (size_t i = 0; i < grey.pixel_count(); ++i)
    for (int c = 0; c < 3; ++c) out.data()[3 * i + c] = grey.data()[i] * tint[c];
  return out;
}

// Views at 0 and 30 deg only: a view at 85 deg extrapolates the statistics far beyond the outer
// ring, where the tone curve's darkest values run below zero. The slices stay finite and
// non-negative in every colour space, and each still gives a measured view's slice back.
TEST(StatisticalBtf, ColourSlicesStayFiniteAndNonNegativeWhereStatisticsExtrapolateBelowZero) {
  SyntheticBtf truth(32, testing::SeedFromTestName());
  const std::vector<Eigen::Vector3d> lights = BonnDirections();
  const std::vector<Eigen::Vector3d> views = {Eigen::Vector3d::UnitZ(), DirectionFromAnglesDeg(30, 0),
                                              DirectionFromAnglesDeg(30, 120), DirectionFromAnglesDeg(30, 240)};
  for (const ColourSpace space : {ColourSpace::kRgb, ColourSpace::kPrincipalAxes, ColourSpace::kChromaticity}) {
    StatisticalBtfOptions options;
    options.colour_space = space;
    std::vector<std::vector<Image>> slices(views.size());
    for (size_t v = 0; v < views.size(); ++v)
      for (const auto& light : lights) slices[v].push_back(Tinted(truth.Slice(light, views[v])));
    options = WithColourChannels(options, slices[0]);
    EXPECT_EQ(options.colour.basis().isIdentity(), space != ColourSpace::kPrincipalAxes);
    std::vector<MeasuredView> measured;
    for (size_t v = 0; v < views.size(); ++v) measured.push_back(MeasureView(views[v], lights, slices[v], options));
    auto btf = StatisticalBtf::Create(slices[0], lights, std::move(measured), options);
    ASSERT_TRUE(btf.ok()) << btf.status().message();
    const Eigen::Vector3d light = DirectionFromAnglesDeg(20, 50), grazing = DirectionFromAnglesDeg(85, 200);
    const SliceStatistics target = btf->TargetStatistics(light, grazing);
    float lowest = 0;
    for (const InverseCdf& q : target.pixels) lowest = std::min(lowest, q.values.front());
    EXPECT_LT(lowest, 0) << "the fixture should extrapolate below zero";
    const Image slice = btf->Reconstruct(light, grazing);
    for (size_t i = 0; i < slice.size(); ++i) ASSERT_TRUE(std::isfinite(slice.data()[i]) && slice.data()[i] >= 0) << i;
    const Image measured_view = btf->Reconstruct(lights[23], views[1]);
    EXPECT_LT(RelativeRms(measured_view, Tinted(truth.Slice(lights[23], views[1]))), 0.08) << ColourSpaceName(space);
  }
}

// The tilted views are measured with another colour than the top view (as a JPEG's half-resolution
// chroma gives the boards whose patches span the fewest pixels): with chromaticity_from_top_view,
// a tilted view's slice keeps the top view's colour and its own brightness; with
// chromaticity_mean_from_views too, the view's own mean colour.
TEST(StatisticalBtf, ChromaticityFromTheTopViewKeepsTheTopViewsColour) {
  SyntheticBtf truth(32, testing::SeedFromTestName());
  const std::vector<Eigen::Vector3d> lights = BonnDirections();
  const std::vector<Eigen::Vector3d> views = {Eigen::Vector3d::UnitZ(), DirectionFromAnglesDeg(30, 0),
                                              DirectionFromAnglesDeg(30, 120), DirectionFromAnglesDeg(30, 240)};
  const float tilted_tint[3] = {0.6f, 0.6f, 0.9f};
  const auto red_share = [](const Image& image) {
    double red = 0, sum = 0;
    for (size_t i = 0; i < image.pixel_count(); ++i)
      red += image.data()[3 * i], sum += image.data()[3 * i] + image.data()[3 * i + 1] + image.data()[3 * i + 2];
    return red / sum;
  };
  for (const int mode : {0, 1, 2}) {  // the views' chromaticity; the top view's; its shape, the views' mean
    const bool from_top = mode == 1;
    StatisticalBtfOptions options;
    options.chromaticity_from_top_view = mode > 0;
    options.chromaticity_mean_from_views = mode == 2;
    std::vector<std::vector<Image>> slices(views.size());
    for (size_t v = 0; v < views.size(); ++v)
      for (const auto& light : lights) slices[v].push_back(Tinted(truth.Slice(light, views[v]), v == 0 ? kOrange : tilted_tint));
    options = WithColourChannels(options, slices[0]);
    std::vector<MeasuredView> measured;
    for (size_t v = 0; v < views.size(); ++v) measured.push_back(MeasureView(views[v], lights, slices[v], options));
    auto btf = StatisticalBtf::Create(slices[0], lights, std::move(measured), options);
    ASSERT_TRUE(btf.ok()) << btf.status().message();
    const Image slice = btf->Reconstruct(lights[23], views[1]);
    EXPECT_NEAR(red_share(slice), from_top ? 1.0 / 1.9 : 0.6 / 2.1, 0.02) << mode;
    double mean = 0, want = 0;
    const Image truth_slice = truth.Slice(lights[23], views[1]);
    for (size_t i = 0; i < slice.pixel_count(); ++i)
      mean += slice.data()[3 * i] + slice.data()[3 * i + 1] + slice.data()[3 * i + 2], want += 2.1 * truth_slice.data()[i];
    EXPECT_NEAR(mean / want, 1.0, 0.05) << "the brightness stays the view's";
  }
}

// A dielectric in colour: an orange body with a Lambertian fall-off plus a white GGX lobe
// (reconstruct/white_lobe.h's model), both scaled by each texel's shading (the texture), the top
// view measured under every Bonn light and the tilted
// views only under lights within 50 deg of their own direction, as the rig's hand-held flash gives
// them. At a held-out view's mirror pair, which no view measured, the truth is whitened by the
// lobe; the reconstruction's colour follows it with white_specular_colour, and its brightness is
// the same either way.
TEST(StatisticalBtf, WhiteSpecularColourWhitensAMirrorPairNoViewMeasured) {
  const SyntheticBtf texture(32, testing::SeedFromTestName());
  constexpr double kAlpha = 0.15, kStrength = 0.8;
  const auto slice = [&](const Eigen::Vector3d& light, const Eigen::Vector3d& view) {
    const double white = kStrength * WhiteLobe::Shape(light, view, kAlpha);
    const float tint[3] = {float(0.3 * light.z() * kOrange[0] + white), float(0.3 * light.z() * kOrange[1] + white),
                           float(0.3 * light.z() * kOrange[2] + white)};
    return Tinted(texture.texture, tint);
  };
  const Eigen::Vector3d view = DirectionFromAnglesDeg(45, 90), mirror = DirectionFromAnglesDeg(45, 270);
  const Image truth = slice(mirror, view);
  Image reconstructed[2];
  for (const bool white : {false, true}) {
    StatisticalBtfOptions options;
    options.white_specular_colour = white;
    auto btf = testing::ReconstructFromRigViews(slice, options);
    ASSERT_TRUE(btf.ok()) << btf.status().message();
    EXPECT_EQ(btf->white_lobe().strength() > 0, white);
    reconstructed[white] = btf->Reconstruct(mirror, view);
  }
  const double truth_saturation = SaturationQuantile(truth, 0.95);
  const double without = SaturationQuantile(reconstructed[0], 0.95) / truth_saturation;
  const double with = SaturationQuantile(reconstructed[1], 0.95) / truth_saturation;
  std::printf("95th-percentile saturation against the truth's: %.3f without, %.3f with the white lobe\n", without, with);
  EXPECT_GT(without, 1.3) << "the fixture's mirror pair should be whiter than the views' colour";
  EXPECT_LT(std::abs(with - 1), 0.1) << with;
  EXPECT_NEAR(MeanRgb(reconstructed[1]).sum() / MeanRgb(reconstructed[0]).sum(), 1.0, 1e-4);
}

// A BTF whose views differ from the top view by an offset, slice(l, v) = top(l) + c(v), where the
// top view changes with the light in a way no single light's slice predicts, measured from the
// top under every Bonn light and from a view tilted 45 deg under the lights with x < 0 only.
struct OneSidedBtf {
  SyntheticBtf texture{32, testing::SeedFromTestName()};
  const Eigen::Vector3d tilted = DirectionFromAnglesDeg(45, 0);
  Image Slice(const Eigen::Vector3d& light, const Eigen::Vector3d& view) const {
    Image out = texture.texture;
    const double gain = 0.5 + 0.4 * light.x() + 0.2 * light.y(), offset = 0.3 * (1 - view.z());
    for (float& value : std::span(out.data(), out.size())) value = float(std::pow(value, 1 + light.x()) * gain + offset);
    return out;
  }
  // `skip_ring_deg`: the tilted view also misses the Bonn lights at that incidence.
  StatusOr<StatisticalBtf> Reconstruction(StatisticalBtfOptions options, double skip_ring_deg = -1) const {
    options.cosine_weighted_lights = false;
    options.match_subbands = false;
    options.mean_model = false;  // these tests are of the blend's statistics; the mean model has its own
    const std::vector<Eigen::Vector3d> all = BonnDirections();
    std::vector<Eigen::Vector3d> one_side;
    for (const auto& l : all)
      if (l.x() < -0.05 && std::abs(AnglesDegFromDirection(l).x() - skip_ring_deg) > 1) one_side.push_back(l);
    std::vector<Image> top, side;
    for (const auto& l : all) top.push_back(Slice(l, Eigen::Vector3d::UnitZ()));
    for (const auto& l : one_side) side.push_back(Slice(l, tilted));
    std::vector<MeasuredView> views = {MeasureView(Eigen::Vector3d::UnitZ(), all, top, options),
                                       MeasureView(tilted, one_side, side, options)};
    return StatisticalBtf::Create(top, all, std::move(views), options);
  }
};

// For a light on the side the tilted view never measured, the paper's blend holds the hull
// edge's statistics (relative error 0.27); the top-view prior, carrying the view's offset whole,
// gives the slice to within the top view's light interpolation (0.014): the offset is measured at
// the edge, the light dependence comes from the top view.
TEST(StatisticalBtf, TheTopViewPriorCarriesLightDependenceBeyondAViewsMeasuredLights) {
  const OneSidedBtf truth;
  const Eigen::Vector3d light = DirectionFromAnglesDeg(50, 20);  // x > 0: outside the tilted view's hull
  for (const bool prior : {true, false}) {
    StatisticalBtfOptions options;
    options.top_view_prior = prior;
    options.far_light_falloff_deg = 0;  // the edge's offset carried however far
    auto btf = truth.Reconstruction(options);
    ASSERT_TRUE(btf.ok()) << btf.status().message();
    ASSERT_FALSE(btf->LightCovered(light, truth.tilted));
    const double error = RelativeRms(btf->Reconstruct(light, truth.tilted), truth.Slice(light, truth.tilted));
    std::printf("top-view prior %d: relative RMS error %.4f\n", int(prior), error);
    if (prior) { EXPECT_LT(error, 0.03); }
    else EXPECT_GT(error, 0.1);
  }
}

// With a falloff, the view's own change from the top view is carried whole within 15 deg of its
// measured lights, and fades beyond: far from them the slice is the top view's at that light.
TEST(StatisticalBtf, AViewsChangeFromTheTopViewFadesFarBeyondItsMeasuredLights) {
  const OneSidedBtf truth;
  StatisticalBtfOptions whole, fading;
  whole.far_light_falloff_deg = 0;
  fading.far_light_falloff_deg = 10;
  auto carried = truth.Reconstruction(whole), faded = truth.Reconstruction(fading);
  ASSERT_TRUE(carried.ok() && faded.ok());
  // Just past the hull's edge (x > -0.05), about 9 deg from the measured light (45, 100).
  const Eigen::Vector3d near = DirectionFromAnglesDeg(40, 88);
  ASSERT_FALSE(faded->LightCovered(near, truth.tilted));
  ASSERT_LT(faded->LightGapDeg(near, truth.tilted), 15);
  EXPECT_LT(RelativeRms(faded->Reconstruct(near, truth.tilted), carried->Reconstruct(near, truth.tilted)), 1e-6);
  // Opposite the measured side, more than 60 deg away: trust below exp(-4.5).
  const Eigen::Vector3d far = DirectionFromAnglesDeg(60, 0);
  ASSERT_GT(faded->LightGapDeg(far, truth.tilted), 60);
  const Image top_view = faded->Reconstruct(far, Eigen::Vector3d::UnitZ());
  const double to_top = RelativeRms(faded->Reconstruct(far, truth.tilted), top_view);
  const double carried_to_top = RelativeRms(carried->Reconstruct(far, truth.tilted), top_view);
  std::printf("far light: faded %.4f, carried %.4f from the top view's slice\n", to_top, carried_to_top);
  EXPECT_LT(to_top, 0.02 * carried_to_top + 1e-3);
}

// Inside the tilted view's hull, at a light of the 30 deg ring it did not measure (the top view
// did): the paper's blend of the view's neighbouring lights (15 and 45 deg rings) misses the top
// view's non-linear light dependence (relative error 0.018); blending the view's change from the
// top view (a constant offset here) and adding the top view's statistics at the light gives the
// slice back (0.0005).
TEST(StatisticalBtf, BlendingAViewsChangeFromTheTopViewKeepsTheTopViewsLightDependence) {
  const OneSidedBtf truth;
  const Eigen::Vector3d light = DirectionFromAnglesDeg(30, 180);
  for (const bool change : {true, false}) {
    StatisticalBtfOptions options;
    options.blend_change_from_top = change;
    auto btf = truth.Reconstruction(options, 30);
    ASSERT_TRUE(btf.ok()) << btf.status().message();
    ASSERT_TRUE(btf->LightCovered(light, truth.tilted));
    ASSERT_GT(btf->LightGapDeg(light, truth.tilted), 10);
    const double error = RelativeRms(btf->Reconstruct(light, truth.tilted), truth.Slice(light, truth.tilted));
    std::printf("change from the top view %d: relative RMS error %.4f\n", int(change), error);
    if (change) { EXPECT_LT(error, 0.002); }
    else EXPECT_GT(error, 0.01);
  }
}

// A texture shaded by a mean brightness law in the mean model's terms
// (reconstruct/mean_brightness_model.h), measured as the rig measures it: the top view under every
// Bonn light, the tilted views (rig's 4 at 30 and 8 at 60 deg) under the lights within 50 deg of
// their own direction.
struct ShadedBtf {
  SyntheticBtf texture{32, testing::SeedFromTestName()};
  // Without a view dependence every view is the top view's: the model cannot beat it.
  bool view_dependent = true;
  double Brightness(const Eigen::Vector3d& l, const Eigen::Vector3d& v) const {
    const double view_terms = view_dependent ? 0.5 * l.dot(v) - 0.4 * v.z() + 0.3 * l.x() * v.x() : 0.0;
    return l.z() * std::exp(view_terms + 0.2 * (l.x() * l.x() - l.y() * l.y()));
  }
  Image Slice(const Eigen::Vector3d& light, const Eigen::Vector3d& view) const {
    Image out = texture.texture;
    for (float& value : std::span(out.data(), out.size())) value *= float(Brightness(light, view));
    return out;
  }
  StatusOr<StatisticalBtf> Reconstruction(bool mean_model) const {
    StatisticalBtfOptions options;
    options.mean_model = mean_model;
    return testing::ReconstructFromRigViews([this](const Eigen::Vector3d& l, const Eigen::Vector3d& v) { return Slice(l, v); },
                                            options);
  }
};

double MeanOf(const Image& image) {
  double sum = 0;
  for (float value : std::span(image.data(), image.size())) sum += value;
  return sum / double(image.size());
}

// Opposite a tilted view's measured lights the blend falls back on the top view's statistics at
// the light, whose mean is the top view's; the mean model gives the view's own mean there.
TEST(StatisticalBtf, TheMeanModelGivesAFarPairTheMeanOfItsView) {
  const ShadedBtf truth;
  auto with = truth.Reconstruction(true), without = truth.Reconstruction(false);
  ASSERT_TRUE(with.ok() && without.ok());
  ASSERT_TRUE(with->mean_model_check().used);
  EXPECT_LT(with->mean_model_check().model_error, 0.2 * with->mean_model_check().top_view_error);
  double worst_with = 0, worst_without = 0;
  for (int phi = 0; phi < 360; phi += 90) {
    const Eigen::Vector3d view = DirectionFromAnglesDeg(45, phi), light = DirectionFromAnglesDeg(50, phi + 180);
    ASSERT_GT(with->LightGapDeg(light, view), 40);
    const double want = MeanOf(truth.Slice(light, view));
    worst_with = std::max(worst_with, std::abs(MeanOf(with->Reconstruct(light, view)) / want - 1));
    worst_without = std::max(worst_without, std::abs(MeanOf(without->Reconstruct(light, view)) / want - 1));
  }
  std::printf("far pairs' mean, worst relative error: %.4f with the mean model, %.4f without\n", worst_with, worst_without);
  EXPECT_LT(worst_with, 0.03);
  EXPECT_GT(worst_without, 0.1);
}

// At a pair a view measured, the light gap is 0 and the slice keeps its blended mean, model or not.
TEST(StatisticalBtf, TheMeanModelLeavesAMeasuredPairAsItIs) {
  const ShadedBtf truth;
  auto with = truth.Reconstruction(true), without = truth.Reconstruction(false);
  ASSERT_TRUE(with.ok() && without.ok());
  // A Bonn light 16 deg from the view: measured.
  const Eigen::Vector3d view = DirectionFromAnglesDeg(60, 45), light = DirectionFromAnglesDeg(45, 40);
  ASSERT_NEAR(with->LightGapDeg(light, view), 0, 1e-6);
  EXPECT_LT(RelativeRms(with->Reconstruct(light, view), without->Reconstruct(light, view)), 1e-6);
}

// Where every view sees what the top view sees, the top view's brightness at a tilted view's
// (Bonn) lights is exact and no model can be nearer: this checks that the check is wired, that its
// verdict leaves the model unfitted and that it ran over the tilted views' slices.
TEST(StatisticalBtf, TheMeanModelIsNotUsedWhereTheTopViewPredictsEveryView) {
  ShadedBtf truth;
  truth.view_dependent = false;
  auto with = truth.Reconstruction(true);
  ASSERT_TRUE(with.ok());
  EXPECT_FALSE(with->mean_model_check().used);
  EXPECT_GT(with->mean_model_check().slices, 100);
  EXPECT_FALSE(with->mean_model().fitted());
}

TEST(StatisticalBtf, RejectsBadInput) {
  SyntheticBtf truth(32, testing::SeedFromTestName());
  Fixture f;
  std::vector<Image> top;
  for (const auto& light : f.lights) top.push_back(truth.Slice(light, f.views[0]));
  MeasuredView view = MeasureView(f.views[0], f.lights, top, {});
  // Different sizes.
  std::vector<Image> mixed = top;
  mixed[3] = Image(16, 16, 1);
  auto r = StatisticalBtf::Create(mixed, f.lights, {view});
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.status().message().find("slice 3"), std::string::npos);
  // Too few lights.
  r = StatisticalBtf::Create({top[0], top[1]}, {f.lights[0], f.lights[1]}, {view});
  EXPECT_FALSE(r.ok());
  // No views.
  r = StatisticalBtf::Create(top, f.lights, {});
  EXPECT_FALSE(r.ok());
}

}  // namespace
}  // namespace mesocap
