#include "capture/btf_render.h"
#include "capture/true_btf_renderer.h"
#include "capture/rig_render.h"

#include <gtest/gtest.h>

#include <numbers>
#include <vector>

#include "core/directions.h"
#include "core/parallel.h"
#include "reconstruct/quantiles.h"

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

TEST(TrueBtfRenderer, SlicesAreTheDirectRendersToTheBitWhetherTheirViewWasCachedOrEvicted) {
  auto stones = Material::Create("stones");
  ASSERT_TRUE(stones.ok());
  TrueBtfRequest grid;
  grid.size = 24;
  grid.samples_per_axis = 2;
  grid.patch_m = 0.05;
  grid.offset_m = {0.013, -0.007};
  grid.material_rotation_deg = 30;
  // Room for two views: the third evicts the least recently used one.
  const size_t two_views = 2 * size_t(24 * 24 * 4) * sizeof(MaterialHit);
  const TrueBtfRenderer renderer(*stones, grid, two_views);
  const std::vector<Eigen::Vector3d> views = {DirectionFromAnglesDeg(0, 0), DirectionFromAnglesDeg(45, 30),
                                              DirectionFromAnglesDeg(70, 200)};
  const std::vector<Eigen::Vector3d> lights = {DirectionFromAnglesDeg(60, 90), DirectionFromAnglesDeg(80, 10)};
  // Traced: 0, 1, (0 reused), 2 evicting 1, 1 evicting 0, 0 evicting 2, 2 evicting 1: 6 traces, 10 slices.
  const std::vector<std::pair<int, int>> order = {{0, 0}, {0, 1}, {1, 0}, {1, 1}, {0, 0},
                                                  {2, 0}, {2, 1}, {1, 1}, {0, 0}, {2, 1}};
  for (const auto& [v, l] : order) {
    TrueBtfRequest direct = TrueBtfRequestFor(lights[l], views[v], grid.size, grid.samples_per_axis);
    direct.patch_m = grid.patch_m;
    direct.offset_m = grid.offset_m;
    direct.material_rotation_deg = grid.material_rotation_deg;
    const Image expected = RenderTrueBtfSlice(*stones, direct, 1);
    const Image got = renderer.Render(lights[l], views[v]);
    ASSERT_EQ(got.size(), expected.size());
    for (size_t k = 0; k < got.size(); ++k) ASSERT_EQ(got.data()[k], expected.data()[k]) << "view " << v << " light " << l;
  }
  EXPECT_EQ(renderer.views_traced(), 6);
}

TEST(TrueBtfRenderer, ThreadsAskingForOneViewTraceItOnce) {
  auto weave = Material::Create("weave");
  ASSERT_TRUE(weave.ok());
  TrueBtfRequest grid;
  grid.size = 16;
  const TrueBtfRenderer renderer(*weave, grid);
  std::vector<Image> slices(16);
  ParallelFor(0, 16, [&](int k) {
    slices[k] = renderer.Render(DirectionFromAnglesDeg(10.0 + 4 * k, 20.0 * k), DirectionFromAnglesDeg(30, 60));
  }, 2);
  EXPECT_EQ(renderer.views_traced(), 1);
  for (int k = 0; k < 16; ++k) {
    const Image direct = RenderTrueBtfSlice(*weave, TrueBtfRequestFor(DirectionFromAnglesDeg(10.0 + 4 * k, 20.0 * k),
                                                                      DirectionFromAnglesDeg(30, 60), 16), 1);
    for (size_t i = 0; i < direct.size(); ++i) ASSERT_EQ(slices[k].data()[i], direct.data()[i]);
  }
}

// Pixel W1 between two slices as `mesocap evaluate` scores it: each channel's values' inverse CDFs
// (reconstruct/quantiles.h), averaged over the channels.
double PixelWasserstein(const Image& a, const Image& b) {
  double total = 0;
  for (int c = 0; c < 3; ++c) {
    std::vector<float> va, vb;
    for (int y = 0; y < a.height(); ++y)
      for (int x = 0; x < a.width(); ++x) va.push_back(a.at(x, y, c)), vb.push_back(b.at(x, y, c));
    total += WassersteinDistance(InverseCdfOf(va), InverseCdfOf(vb));
  }
  return total / 3.0;
}

TEST(TrueBtf, TheRigsTruthSamplingConvergesTheTexelAverage) {
  // The rig shades each patch on 512 points a side: a 64-texel truth averages 8 x 8 of them.
  EXPECT_EQ(RigTruthSamplesPerAxis(64), 8);
  EXPECT_EQ(RigTruthSamplesPerAxis(128), 4);
  EXPECT_EQ(RigTruthSamplesPerAxis(1024), 2);
  EXPECT_EQ(RigTruthSamplesPerAxis(64, {.patch_texels = 256}), 4);
  // Against a 16 x 16 reference, that truth's histograms sit far nearer than 2 x 2's.
  auto weave = Material::Create("weave");
  ASSERT_TRUE(weave.ok());
  const auto render = [&](int samples) {
    TrueBtfRequest request{45, 30, 30, 200, 64};
    request.samples_per_axis = samples;
    return RenderTrueBtfSlice(*weave, request);
  };
  const Image reference = render(16);
  const double coarse = PixelWasserstein(render(2), reference), rule = PixelWasserstein(render(RigTruthSamplesPerAxis(64)), reference);
  EXPECT_LT(rule, coarse / 3) << "2 x 2: " << coarse << ", 8 x 8: " << rule;
}

TEST(Materials, UnknownNameListsTheChoices) {
  auto m = Material::Create("velvet");
  ASSERT_FALSE(m.ok());
  EXPECT_NE(m.status().message().find("weave"), std::string::npos);
}

}  // namespace
}  // namespace mesocap
