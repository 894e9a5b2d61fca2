// The shared separable filter against closed-form answers: the mirrored index, a constant kept, an
// impulse spread into the outer product of the taps (spaced by the step), and two channels apart.
#include <gtest/gtest.h>

#include "synth/separable_filter.h"

namespace mesocap {
namespace {

TEST(MirrorIndex101, ReflectsAboutTheEndTexels) {
  const int expected[] = {3, 2, 1, 0, 1, 2, 3, 2, 1, 0};  // i = -3 .. 6 on n = 4
  for (int i = -3; i <= 6; ++i) EXPECT_EQ(MirrorIndex101(i, 4), expected[i + 3]) << i;
  EXPECT_EQ(MirrorIndex101(-5, 1), 0);
  EXPECT_EQ(MirrorIndex101(7, 1), 0);
}

TEST(SeparableFilter, KeepsAConstantAndSpreadsAnImpulseIntoTheTapsOuterProduct) {
  const std::vector<float> taps = {0.25f, 0.5f, 0.25f};
  const Image flat = SeparableFilter(Image(9, 7, 2, 0.75f), taps, 2);
  for (size_t i = 0; i < flat.size(); ++i) EXPECT_FLOAT_EQ(flat.data()[i], 0.75f);

  Image impulse(15, 13, 2);
  impulse.at(7, 6, 1) = 1;
  for (int step : {1, 3}) {
    const Image out = SeparableFilter(impulse, taps, step);
    for (int y = 0; y < 13; ++y)
      for (int x = 0; x < 15; ++x) {
        auto tap = [&](int d) { return d % step == 0 && std::abs(d / step) <= 1 ? taps[d / step + 1] : 0.f; };
        EXPECT_FLOAT_EQ(out.at(x, y, 1), tap(x - 7) * tap(y - 6)) << x << "," << y << " step " << step;
        EXPECT_EQ(out.at(x, y, 0), 0.f);
      }
  }
}

}  // namespace
}  // namespace mesocap
