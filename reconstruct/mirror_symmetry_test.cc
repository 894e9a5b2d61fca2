#include "reconstruct/mirror_symmetry.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "capture/rig_material.h"
#include "capture/true_btf_renderer.h"
#include "core/directions.h"
#include "reconstruct/quantiles.h"
#include "reconstruct/statistical_btf.h"

namespace mesocap {
namespace {

// Diagonal stripes at 30 deg plus noise: a texture whose mirror image differs from it.
Image SlantedStripes(int size) {
  Image image(size, size, 1);
  std::mt19937 rng(5);
  std::normal_distribution<float> noise(0.0f, 0.05f);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x)
      image.data()[size_t(y) * size + x] = 0.5f + 0.3f * float(std::sin(0.7 * (x * 0.866 + y * 0.5))) + noise(rng);
  return image;
}

// The square image `image` imaged by `image_of` in the patch frame (x along the columns, y up the
// rows, about the centre): out(p) = image(A^-1 p).
Image Imaged(const Image& image, const MirrorImage& image_of) {
  const int n = image.width();
  const double c = (n - 1) / 2.0;
  Image out(n, n, image.channels());
  for (int row = 0; row < n; ++row)
    for (int col = 0; col < n; ++col) {
      const Eigen::Vector2d source = image_of.plane.transpose() * Eigen::Vector2d(col - c, c - row);
      out.data()[size_t(row) * n + col] =
          image.data()[size_t(std::lround(c - source.y())) * n + size_t(std::lround(source.x() + c))];
    }
  return out;
}

TEST(MirrorSymmetry, ImagedStatisticsAreThoseOfTheImagedTexture) {
  const Image texture = SlantedStripes(64);
  const SliceStatistics original = ComputeSliceStatistics(texture);
  for (const MirrorImage& image : MirrorImages()) {
    const SliceStatistics truth = ComputeSliceStatistics(Imaged(texture, image));
    const SliceStatistics imaged = ImagedStatistics(original, image, 4);
    ASSERT_EQ(imaged.band_count, truth.band_count);
    EXPECT_LT(WassersteinDistance(imaged.pixels[0], truth.pixels[0]), 1e-6);
    double not_imaged = 0;
    for (int b = 0; b < truth.band_count; ++b) {
      const double spread = truth.band(0, b).At(0.9) - truth.band(0, b).At(0.1);
      // The finest scale's bands to round-off; the coarser ones are sampled on a lattice the flip
      // moves by half a texel, which shifts their histograms by a few percent of their spread.
      const double tolerance = b <= 4 ? 1e-5 : 0.05;
      EXPECT_LT(WassersteinDistance(imaged.band(0, b), truth.band(0, b)), tolerance * spread)
          << image.name << " band " << b;
      not_imaged = std::max(not_imaged, WassersteinDistance(original.band(0, b), truth.band(0, b)) / spread);
    }
    // Left as they were, the bands differ: the test can fail.
    // (The half turn only negates the bands, whose histograms are nearly even.)
    EXPECT_GT(not_imaged, image.plane.isApprox(-Eigen::Matrix2d::Identity()) ? 0.005 : 0.5) << image.name;
  }
}

TEST(MirrorSymmetry, BlendingThroughBandMapsEqualsBlendingImagedCopies) {
  // Statistics of two textures (3 channels), one of them read through each image's band map: the
  // blend equals, to the bit, the blend of the imaged copy (negative weight included).
  const auto three_channels = [](const Image& grey, float tint) {
    Image rgb(grey.width(), grey.height(), 3);
    for (size_t i = 0; i < grey.size(); ++i)
      for (int c = 0; c < 3; ++c) rgb.data()[i * 3 + c] = grey.data()[i] * (1.0f + tint * float(c));
    return rgb;
  };
  const SliceStatistics a = ComputeSliceStatistics(three_channels(SlantedStripes(32), 0.2f));
  const SliceStatistics b = ComputeSliceStatistics(three_channels(Imaged(SlantedStripes(32), MirrorImages()[5]), -0.1f));
  const std::vector<std::vector<double>> weights = {{1.3, -0.3}, {0.6, 0.4}, {0.2, 0.8}};
  for (const MirrorImage& image : MirrorImages()) {
    const BandMap map = ImagedBands(image, a.band_count, 4);
    const SliceStatistics imaged = ImagedStatistics(b, image, 4);
    const std::vector<const SliceStatistics*> copies = {&a, &imaged}, sources = {&a, &b};
    const std::vector<const BandMap*> maps = {nullptr, &map};
    const SliceStatistics expected = BlendSliceStatistics(copies, weights);
    const SliceStatistics mapped = BlendSliceStatistics(sources, weights, maps);
    ASSERT_EQ(mapped.bands.size(), expected.bands.size());
    for (size_t k = 0; k < expected.pixels.size(); ++k) EXPECT_EQ(mapped.pixels[k].values, expected.pixels[k].values);
    int moved = 0;
    for (size_t k = 0; k < expected.bands.size(); ++k) {
      EXPECT_EQ(mapped.bands[k].values, expected.bands[k].values) << image.name << " band " << k;
      moved += map.from[k % size_t(a.band_count)] != int(k % size_t(a.band_count)) || map.negated[k % size_t(a.band_count)];
    }
    EXPECT_GT(moved, 0) << image.name << ": the map moves or negates some band";
  }
}

TEST(MirrorSymmetry, ImagesOfABoardPoolWithTheBoardsTheyLandOn) {
  // Two 30 deg views half a turn apart, each lit from its own side, and one 60 deg view.
  const auto view_at = [](double theta, double phi, std::vector<Eigen::Vector3d> lights) {
    MeasuredView view;
    view.view = DirectionFromAnglesDeg(theta, phi);
    view.lights = std::move(lights);
    view.statistics.assign(view.lights.size(), ComputeSliceStatistics(SlantedStripes(32)));
    return view;
  };
  const std::vector<MeasuredView> views = {
      view_at(30, 0, {DirectionFromAnglesDeg(20, 10), DirectionFromAnglesDeg(40, 0), DirectionFromAnglesDeg(30, 330)}),
      view_at(30, 181, {DirectionFromAnglesDeg(20, 170), DirectionFromAnglesDeg(45, 200), DirectionFromAnglesDeg(30, 180)}),
      view_at(60, 90, {DirectionFromAnglesDeg(50, 80), DirectionFromAnglesDeg(60, 100), DirectionFromAnglesDeg(70, 90)})};
  // The half turn alone: the two 30 deg views pool, the 60 deg view's image becomes a view at 270.
  const std::vector<MeasuredView> pooled =
      WithMirrorImages(views, {false, false, true, false, false, false, false}, kMirrorPoolDeg, 0.25);
  ASSERT_EQ(pooled.size(), 4u);
  EXPECT_EQ(pooled[0].lights.size(), 6u);
  EXPECT_EQ(pooled[1].lights.size(), 6u);
  // The first view's own lights first, then the second's turned half round: (20, 170) -> (20, 350).
  EXPECT_LT(AngleBetweenDeg(pooled[0].lights[3], DirectionFromAnglesDeg(20, 350)), 1e-9);
  // Lent, not copied: the measured statistics stay 3, and the borrowed light names its source.
  EXPECT_EQ(pooled[0].statistics.size(), 3u);
  ASSERT_EQ(pooled[0].borrowed.size(), 3u);
  EXPECT_EQ(pooled[0].borrowed[0].view, 1);
  EXPECT_EQ(pooled[0].borrowed[0].light, 0);
  EXPECT_EQ(pooled[0].borrowed[0].image, 2);
  EXPECT_LT(AngleBetweenDeg(pooled[3].view, DirectionFromAnglesDeg(60, 270)), 1e-9);
  EXPECT_EQ(pooled[3].lights.size(), 3u);
  // A mirror image landing on a light a view has adds nothing there: (30, 180) mirrored in y.
  const std::vector<MeasuredView> mirrored =
      WithMirrorImages(views, {true, true, true, false, false, false, false}, kMirrorPoolDeg, 0.25);
  ASSERT_EQ(mirrored.size(), 4u);
  // Each 30 deg view: its own 3 lights and 5 of the other's and its own images (7 of the 9 land on
  // a light already there, e.g. (20, 10) mirrored in x on (20, 170)).
  EXPECT_EQ(mirrored[0].lights.size(), 8u);
  EXPECT_EQ(mirrored[1].lights.size(), 8u);
  // The 60 deg view at 90 and its image at 270: 3 lights each and 2 mirrored in x ((70, 90) is its own image).
  EXPECT_EQ(mirrored[2].lights.size(), 5u);
  EXPECT_EQ(mirrored[3].lights.size(), 5u);
}

// 150 lights spread over the hemisphere to 65 deg (a Fibonacci spiral, 9 deg apart).
std::vector<Eigen::Vector3d> SpreadLights() {
  std::vector<Eigen::Vector3d> lights;
  const int n = 150;
  const double min_z = std::cos(65 * M_PI / 180), golden = M_PI * (3 - std::sqrt(5.0));
  for (int k = 0; k < n; ++k) {
    const double z = 1 - (1 - min_z) * (k + 0.5) / n, r = std::sqrt(1 - z * z);
    lights.emplace_back(r * std::cos(golden * k), r * std::sin(golden * k), z);
  }
  return lights;
}

MeasuredView TopView(const std::vector<Eigen::Vector3d>& lights, const std::vector<Image>& slices) {
  return MeasureView(Eigen::Vector3d::UnitZ(), lights, slices, WithColourChannels({}, slices));
}

// True slices of a virtual material seen from the top under SpreadLights, 32 texels over 32 mm
// (1 mm a texel, as the evaluation's 64 texels on the rig's patch).
MeasuredView TopViewOf(const std::string& name) {
  auto material = Material::Create(name);
  EXPECT_TRUE(material.ok());
  TrueBtfRequest grid;
  grid.size = 32;
  grid.patch_m = 0.032;
  grid.samples_per_axis = 2;
  const TrueBtfRenderer renderer(*material, grid);
  const std::vector<Eigen::Vector3d> lights = SpreadLights();
  std::vector<Image> slices(lights.size());
  for (size_t k = 0; k < lights.size(); ++k) slices[k] = renderer.Render(lights[k], Eigen::Vector3d::UnitZ());
  return TopView(lights, slices);
}

TEST(MirrorSymmetry, TheCheckFindsWhichImagesOfTheVirtualMaterialsHold) {
  // The virtual weave's fibres twist one way: turned half round it looks the same, mirrored not.
  const MirrorSymmetryCheck weave = CheckMirrorSymmetry(TopViewOf("weave"), 4, 0.25);
  const MirrorSymmetryCheck stones = CheckMirrorSymmetry(TopViewOf("stones"), 4, 0.25);
  const MirrorSymmetryCheck corduroy = CheckMirrorSymmetry(TopViewOf("corduroy"), 4, 0.25);
  for (size_t k = 0; k < MirrorImages().size(); ++k)
    std::printf("%-20s weave %.2f %.2f %d, stones %.2f %.2f %d, corduroy %.2f %.2f %d\n", MirrorImages()[k].name,
                weave.ratio[k], weave.against_measured[k], int(weave.holds[k]), stones.ratio[k],
                stones.against_measured[k], int(stones.holds[k]), corduroy.ratio[k], corduroy.against_measured[k],
                int(corduroy.holds[k]));
  for (size_t k = 0; k < MirrorImages().size(); ++k) {
    EXPECT_GT(weave.lights[k], 50);
    // Stones are isotropic: every image holds.
    EXPECT_TRUE(stones.holds[k]) << MirrorImages()[k].name;
    // Corduroy's wales run along y: the mirrors and the half turn hold, the quarter turns not.
    EXPECT_EQ(corduroy.holds[k], k < 3) << MirrorImages()[k].name;
    // The weave's fibres twist one way and its warp and weft differ: the half turn holds, the mirrors
    // about the axes, the quarter turns and the mirror about the antidiagonal not. The mirror about
    // the diagonal swaps warp and weft, which have the same relief and share the patch alike: on
    // this patch the brightness statistics, which keep no tie between orientation and colour, do
    // not tell (from calibrated JPEG sessions it fails: docs/reconstruction.md).
    EXPECT_EQ(weave.holds[k], k == 2 || k == 5) << MirrorImages()[k].name;
  }
}

TEST(MirrorSymmetry, TheCheckFindsOnlyTheImagesTheOperatorNamed) {
  // Stones pass every image; named the half turn and the mirror about x, the check holds those two
  // and still measures the others.
  const MeasuredView stones = TopViewOf("stones");
  const MirrorImageSet named = MirrorImagesNamed({"half_turn", "mirror_x"});
  const MirrorSymmetryCheck free = CheckMirrorSymmetry(stones, 4, 0.25);
  const MirrorSymmetryCheck bound = CheckMirrorSymmetry(stones, 4, 0.25, 10, named);
  for (size_t k = 0; k < MirrorImages().size(); ++k) {
    ASSERT_TRUE(free.holds[k]) << MirrorImages()[k].name;
    EXPECT_EQ(bound.holds[k], k == 0 || k == 2) << MirrorImages()[k].name;
    EXPECT_EQ(bound.allowed[k], named[k]);
    EXPECT_EQ(bound.ratio[k], free.ratio[k]);
    EXPECT_EQ(bound.lights[k], free.lights[k]);
  }
  // Named but disproved still fails: the weave's mirror about x.
  const MirrorSymmetryCheck weave = CheckMirrorSymmetry(TopViewOf("weave"), 4, 0.25, 10, named);
  EXPECT_FALSE(weave.holds[0]);
  EXPECT_TRUE(weave.holds[2]);
  EXPECT_EQ(MirrorImagesNamed({}), MirrorImageSet{});
}

TEST(MirrorSymmetry, NoImageHoldsForATextureThatFollowsTheLightsAzimuth) {
  // Stripes whose contrast grows with cos(phi - 30 deg) of the light: no image of the light keeps it.
  const std::vector<Eigen::Vector3d> lights = SpreadLights();
  const Image stripes = SlantedStripes(32);
  std::vector<Image> slices;
  for (const Eigen::Vector3d& light : lights) {
    const double contrast = 0.2 + 0.8 * (1 + std::cos(std::atan2(light.y(), light.x()) - M_PI / 6)) / 2;
    Image slice = stripes;
    for (size_t i = 0; i < slice.size(); ++i) slice.data()[i] = float(0.5 + contrast * (stripes.data()[i] - 0.5));
    slices.push_back(slice);
  }
  const MirrorSymmetryCheck check = CheckMirrorSymmetry(TopView(lights, slices), 4, 0.25);
  EXPECT_TRUE(check.tested);
  for (size_t k = 0; k < MirrorImages().size(); ++k)
    EXPECT_FALSE(check.holds[k]) << MirrorImages()[k].name << " " << check.ratio[k];
}

}  // namespace
}  // namespace mesocap
