// The mean brightness model: a law in its terms is recovered from the rig's one-sided coverage and
// predicted where no view measured; too few samples give no model; the measured pairs' errors
// are added back near them.
#include "reconstruct/mean_brightness_model.h"

#include <cmath>

#include <gtest/gtest.h>

#include "core/directions.h"
#include "reconstruct/btf_evaluation.h"
#include "reconstruct/rig_coverage_testing.h"

namespace mesocap {
namespace {

// The rig's 13 views: the top one under lights all over the hemisphere, the tilted ones under
// lights within 50 deg of their own direction (the flash on the camera's side).
template <typename Law>
std::vector<MeanBrightnessSample> RigSamples(const Law& law) {
  const std::vector<Eigen::Vector3d> views = RigViewDirections();
  std::vector<MeanBrightnessSample> samples;
  for (const Eigen::Vector3d& view : views)
    for (int theta = 0; theta <= 80; theta += 10)
      for (int phi = 0; phi < 360; phi += 20) {
        const Eigen::Vector3d light = DirectionFromAnglesDeg(theta, phi);
        if (!testing::RigViewMeasures(view, light)) continue;
        samples.push_back({light, view, law(light, view)});
      }
  return samples;
}

// cos(theta_i) times the exponential of a few of the model's terms: a brighter retro-reflection
// (l.v), a darker grazing view, and a grain along x.
double LawInTheTerms(const Eigen::Vector3d& l, const Eigen::Vector3d& v) {
  return l.z() * std::exp(-1.0 + 0.4 * l.dot(v) - 0.3 * v.z() + 0.2 * l.x() * v.x() + 0.1 * (l.x() * l.x() - l.y() * l.y()));
}

TEST(MeanBrightnessModel, PredictsALawInItsTermsWhereNoTiltedViewMeasured) {
  const MeanBrightnessModel model = MeanBrightnessModel::Fit(RigSamples(LawInTheTerms));
  ASSERT_TRUE(model.fitted());
  double worst = 0;
  for (int phi_o = 0; phi_o < 360; phi_o += 45)
    for (int theta_i = 20; theta_i <= 70; theta_i += 25) {
      // The light on the far side of a 45 deg view: no tilted view measured near it.
      const Eigen::Vector3d view = DirectionFromAnglesDeg(45, phi_o), light = DirectionFromAnglesDeg(theta_i, phi_o + 180);
      worst = std::max(worst, std::abs(model.Predict(light, view) / LawInTheTerms(light, view) - 1));
    }
  std::printf("worst relative error at far pairs: %.2e\n", worst);
  EXPECT_LT(worst, 0.02);  // not exact: the ridge shrinks the terms a little (1.5% at worst)
}

// Near a measured pair the model's error there is added back: a bump the terms cannot express is
// predicted at a neighbouring pair far better than by the fitted terms alone.
TEST(MeanBrightnessModel, AddsBackTheErrorOfTheMeasuredPairsNearby) {
  const Eigen::Vector3d bump_view = DirectionFromAnglesDeg(60, 90), bump_light = DirectionFromAnglesDeg(40, 90);
  const auto law = [&](const Eigen::Vector3d& l, const Eigen::Vector3d& v) {
    const double distance = AngleBetweenDeg(l, bump_light) + AngleBetweenDeg(v, bump_view);
    return LawInTheTerms(l, v) * (1 + 0.3 * std::exp(-distance * distance / 400));
  };
  const MeanBrightnessModel with_bump = MeanBrightnessModel::Fit(RigSamples(law));
  ASSERT_TRUE(with_bump.fitted());
  const Eigen::Vector3d view = DirectionFromAnglesDeg(60, 90), light = DirectionFromAnglesDeg(45, 95);  // between lights
  const double error = std::abs(with_bump.Predict(light, view) / law(light, view) - 1);
  const double bump = law(light, view) / LawInTheTerms(light, view) - 1;
  std::printf("bump %.3f, error with the measured pairs' errors added back %.4f\n", bump, error);
  EXPECT_GT(bump, 0.2);
  EXPECT_LT(error, 0.3 * bump);  // 0.26: the bump is narrower than the 15 deg of the pairs averaged
}

TEST(MeanBrightnessModel, TooFewOrUnusableSamplesGiveNoModel) {
  std::vector<MeanBrightnessSample> samples = RigSamples(LawInTheTerms);
  samples.resize(2 * MeanBrightnessModel::kTerms - 1);
  EXPECT_FALSE(MeanBrightnessModel::Fit(samples).fitted());
  EXPECT_EQ(MeanBrightnessModel::Fit(samples).Predict(Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitZ()), 0.0);
  // Dark, non-finite and grazing samples are left out: mixed into a good set, they change nothing.
  const MeanBrightnessModel model = MeanBrightnessModel::Fit(RigSamples(LawInTheTerms));
  std::vector<MeanBrightnessSample> mixed = RigSamples(LawInTheTerms);
  for (int k = 0; k < 20; ++k) {
    const Eigen::Vector3d light = DirectionFromAnglesDeg(10 + 3 * k, 17 * k), view = DirectionFromAnglesDeg(30, 90);
    mixed.push_back({light, view, k % 3 == 0 ? 0.0 : k % 3 == 1 ? std::nan("") : -1.0});
    mixed.push_back({DirectionFromAnglesDeg(88, 17 * k), view, 100.0});  // grazing, and far off the law
  }
  const MeanBrightnessModel fitted_with_bad = MeanBrightnessModel::Fit(mixed);
  ASSERT_TRUE(fitted_with_bad.fitted());
  for (const auto& [light, view] : {std::pair{DirectionFromAnglesDeg(40, 200), DirectionFromAnglesDeg(45, 20)},
                                    std::pair{DirectionFromAnglesDeg(20, 10), DirectionFromAnglesDeg(15, 300)}})
    EXPECT_DOUBLE_EQ(fitted_with_bad.Predict(light, view), model.Predict(light, view));
  // A light below the horizon gets no prediction.
  EXPECT_EQ(model.Predict(Eigen::Vector3d(1, 0, -0.1), Eigen::Vector3d::UnitZ()), 0.0);
}

}  // namespace
}  // namespace mesocap
