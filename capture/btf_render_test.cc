#include "capture/btf_render.h"

#include <gtest/gtest.h>

#include <numbers>

namespace mesocap {
namespace {

double Mean(const Image& im, int c) {
  double sum = 0;
  for (int y = 0; y < im.height(); ++y)
    for (int x = 0; x < im.width(); ++x) sum += im.at(x, y, c);
  return sum / im.pixel_count();
}

TEST(TrueBtf, FlatConstantAlbedoGivesAlbedoOverPiTimesCosThetaI) {
  auto flat = Material::Create("flat");
  ASSERT_TRUE(flat.ok());
  for (double ti : {0.0, 20.0, 45.0, 60.0, 75.0})
    for (double to : {0.0, 30.0, 60.0, 75.0})
      for (double pi : {0.0, 130.0}) {
        const Image slice = RenderTrueBtfSlice(*flat, {ti, pi, to, 250.0, 32});
        const double expected = 0.5 / std::numbers::pi * std::cos(ti * std::numbers::pi / 180);
        for (int c = 0; c < 3; ++c) {
          EXPECT_NEAR(Mean(slice, c), expected, 0.01 * expected) << ti << " " << to;
          // Every texel, not just the mean.
          for (int y = 0; y < slice.height(); y += 7)
            for (int x = 0; x < slice.width(); x += 7) EXPECT_NEAR(slice.at(x, y, c), expected, 0.01 * expected);
        }
      }
}

TEST(TrueBtf, HeightFieldCastsShadowsOnlyAwayFromZenith) {
  auto stones = Material::Create("stones");
  ASSERT_TRUE(stones.ok());
  auto black_fraction = [&](double theta_i) {
    const Image s = RenderTrueBtfSlice(*stones, {theta_i, 30, 0, 0, 128});
    int black = 0;
    for (int y = 0; y < s.height(); ++y)
      for (int x = 0; x < s.width(); ++x) black += s.at(x, y, 0) == 0.0f;
    return double(black) / s.pixel_count();
  };
  EXPECT_EQ(black_fraction(0), 0.0);     // a height field cannot shadow light from straight above
  EXPECT_GT(black_fraction(80), 0.05);   // grazing light: mortar and stone flanks in shadow
}

TEST(TrueBtf, ViewRayFindsTheFirstSurfaceAlongTheRay) {
  auto corduroy = Material::Create("corduroy");
  ASSERT_TRUE(corduroy.ok());
  const Eigen::Vector3d wo = Eigen::Vector3d(std::sin(1.0), 0, std::cos(1.0));
  for (double x = 0.001; x < 0.01; x += 0.0007) {
    const MaterialHit hit = TraceFromViewer(*corduroy, x, 0.002, wo);
    // The hit lies on the surface and on the ray through (x, y, 0).
    EXPECT_NEAR(hit.point.z(), corduroy->Height(hit.point.x(), hit.point.y()), 2e-6);
    const double s = hit.point.z() / wo.z();
    EXPECT_NEAR(hit.point.x(), x + s * wo.x(), 1e-6);
    // Nothing of the surface is above the ray between the viewer and the hit.
    for (double t = s + 1e-5; t < corduroy->max_height_m() / wo.z(); t += 2e-5)
      EXPECT_GE(t * wo.z(), corduroy->Height(x + t * wo.x(), 0.002) - 1e-6);
  }
}

TEST(Materials, UnknownNameListsTheChoices) {
  auto m = Material::Create("velvet");
  ASSERT_FALSE(m.ok());
  EXPECT_NE(m.status().message().find("weave"), std::string::npos);
}

}  // namespace
}  // namespace mesocap
