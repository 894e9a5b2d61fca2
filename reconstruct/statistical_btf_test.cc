#include "reconstruct/statistical_btf.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "core/directions.h"
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

// A Lambertian-like BTF, texture x cos(theta_i), measured under a few lights far apart: blending
// the cosine-normalised slices gives any light's slice exactly; blending values as measured
// (the paper's) does not.
TEST(StatisticalBtf, CosineWeightedLightsInterpolateALambertianFalloffExactly) {
  SyntheticBtf texture(32, testing::SeedFromTestName());
  std::vector<Eigen::Vector3d> lights = {Eigen::Vector3d::UnitZ()};
  for (int k = 0; k < 5; ++k) lights.push_back(DirectionFromAnglesDeg(70, 72.0 * k));
  auto slice = [&](const Eigen::Vector3d& l) {
    Image out = texture.texture;
    for (size_t i = 0; i < out.size(); ++i) out.data()[i] *= float(l.z());
    return out;
  };
  std::vector<Image> top;
  for (const auto& l : lights) top.push_back(slice(l));
  const Eigen::Vector3d query = DirectionFromAnglesDeg(40, 100);
  for (const bool cosine : {true, false}) {
    StatisticalBtfOptions options;
    options.cosine_weighted_lights = cosine;
    auto btf = StatisticalBtf::Create(top, lights, {MeasureView(Eigen::Vector3d::UnitZ(), lights, top, options)}, options);
    ASSERT_TRUE(btf.ok()) << btf.status().message();
    const double error = RelativeRms(btf->BaseTexture(query), slice(query));
    if (cosine) { EXPECT_LT(error, 1e-5); }
    else EXPECT_GT(error, 0.05);
  }
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
