// The white specular lobe: the split of a mean colour into body colour and white, and the fit of
// the lobe to samples drawn from a known lobe over the rig's kind of coverage.
#include "reconstruct/white_lobe.h"

#include <cmath>

#include <gtest/gtest.h>

#include "core/directions.h"
#include "reconstruct/btf_evaluation.h"
#include "reconstruct/rig_coverage_testing.h"

namespace mesocap {
namespace {

const Eigen::Vector3d kBody(0.5, 0.3, 0.2);  // a chromaticity: sums to 1

TEST(WhiteLobe, WhitePartIsWhatAddsToTheBodyColourEqually) {
  for (double d : {0.0, 0.1, 2.0})
    for (double s : {0.0, 0.05, 1.0}) {
      const Eigen::Vector3d mean = d * kBody + Eigen::Vector3d::Constant(s);
      EXPECT_NEAR(WhiteLobe::WhitePart(mean, kBody), s, 1e-12) << d << " " << s;
    }
  // A grey body cannot be told from white.
  EXPECT_EQ(WhiteLobe::WhitePart(Eigen::Vector3d(0.2, 0.2, 0.2), Eigen::Vector3d::Constant(1.0 / 3)), 0.0);
}

// Mean colours as the rig measures them: a head-on view under lights all over the hemisphere, and
// tilted views under lights within 50 deg of their own direction (the flash on the camera's side);
// each the body colour times a Lambertian cosine plus `strength` times the lobe of roughness `alpha`.
std::vector<MeanColourSample> RigSamples(double strength, double alpha) {
  const std::vector<Eigen::Vector3d> views = RigViewDirections();
  std::vector<MeanColourSample> samples;
  for (const Eigen::Vector3d& view : views)
    for (int t = 0; t <= 80; t += 8)
      for (int p = 0; p < 360; p += 20) {
        const Eigen::Vector3d light = DirectionFromAnglesDeg(t, p);
        if (!testing::RigViewMeasures(view, light)) continue;
        const double white = strength * WhiteLobe::Shape(light, view, alpha);
        samples.push_back({light, view, 0.3 * light.z() * kBody + Eigen::Vector3d::Constant(white)});
      }
  return samples;
}

TEST(WhiteLobe, FitRecoversANarrowLobeFromTheRigsCoverage) {
  for (const double alpha : {0.1, 0.2}) {
    const WhiteLobe lobe = WhiteLobe::Fit(RigSamples(0.8, alpha));
    EXPECT_NEAR(lobe.alpha(), alpha, 0.06 * alpha) << alpha;  // the grid's steps are 6% apart
    EXPECT_NEAR(lobe.strength(), 0.8, 0.1) << alpha;
    EXPECT_LT((lobe.body_chromaticity() - kBody).norm(), 0.01);
    // What no tilted view measured: the mirror pair of a 60 deg view.
    const Eigen::Vector3d view = DirectionFromAnglesDeg(60, 0), mirror = DirectionFromAnglesDeg(60, 180);
    EXPECT_NEAR(lobe.Radiance(mirror, view), 0.8 * WhiteLobe::Shape(mirror, view, alpha),
                0.15 * 0.8 * WhiteLobe::Shape(mirror, view, alpha));
  }
}

// The most saturated samples are taken as without white; a broad lobe leaves some in them, and
// the fit then finds less white than there is, never more.
TEST(WhiteLobe, ABroadLobeIsUnderestimated) {
  const WhiteLobe lobe = WhiteLobe::Fit(RigSamples(0.8, 0.4));
  EXPECT_GT(lobe.strength(), 0.5 * 0.8);
  EXPECT_LT(lobe.strength(), 0.8);
  EXPECT_NEAR(lobe.alpha(), 0.4, 0.15 * 0.4);
}

TEST(WhiteLobe, NoLobeFromTooFewOrWhitelessOrImplausibleSamples) {
  const auto samples = RigSamples(0.8, 0.3);
  EXPECT_EQ(WhiteLobe::Fit({samples.begin(), samples.begin() + WhiteLobe::kMinSamples - 1}).strength(), 0);
  EXPECT_LT(WhiteLobe::Fit(RigSamples(0.0, 0.3)).strength(), 1e-9);  // purely diffuse
  EXPECT_EQ(WhiteLobe::Fit(RigSamples(3 * WhiteLobe::kMaxStrength, 0.3)).strength(), 0);
  std::vector<MeanColourSample> grey = samples;  // a grey body: white cannot be told apart
  for (MeanColourSample& s : grey) s.mean_rgb = Eigen::Vector3d::Constant(s.mean_rgb.mean());
  EXPECT_EQ(WhiteLobe::Fit(grey).strength(), 0);
  EXPECT_EQ(WhiteLobe().Radiance(Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitZ()), 0);
}

}  // namespace
}  // namespace mesocap
