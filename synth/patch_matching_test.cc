#include "synth/patch_matching.h"

#include <cmath>
#include <random>
#include <tuple>

#include <gtest/gtest.h>

#include "tests/testing.h"

namespace mesocap {
namespace {

Image RandomImage(int w, int h, int channels, std::mt19937& rng) {
  Image image(w, h, channels);
  std::uniform_real_distribution<float> u(0, 1);
  for (size_t i = 0; i < image.size(); ++i) image.data()[i] = u(rng);
  return image;
}

TEST(PatchMatching, FftCostsEqualBruteForceWithRotationsAndConstraint) {
  std::mt19937 rng(testing::SeedFromTestName());
  const Image sample = RandomImage(40, 36, 5, rng);
  const Image sample_mask = RandomImage(40, 36, 1, rng);
  const Image output = RandomImage(50, 45, 5, rng);
  const Image target = RandomImage(50, 45, 1, rng);
  std::vector<uint8_t> synthesized(50 * 45);
  for (auto& s : synthesized) s = rng() % 3 != 0;
  std::vector<RotatedSample> copies;
  for (double r : {0.0, 30.0, 90.0, 215.0}) copies.push_back(MakeRotatedSample(sample, sample_mask, r));
  // A window's constraint scale multiplies the matcher's weight (painting's region rule raises it).
  for (auto [weight, scale] : {std::pair{0.0, 1.0}, {0.7, 1.0}, {0.7, 8.0}}) {
    PatchMatcher matcher(copies, {weight, 2});
    MatchWindow window{11, 9, &output, &synthesized, &target, 17, 23, scale};
    for (int k = 0; k < int(copies.size()); ++k) {
      int fw = 0, fh = 0, bw = 0, bh = 0;
      const auto fft = matcher.Costs(window, k, &fw, &fh);
      const auto brute = BruteForceCosts(copies[k], window, weight * scale, &bw, &bh);
      ASSERT_EQ(fw, bw);
      ASSERT_EQ(fh, bh);
      ASSERT_GT(fw, 0);
      for (size_t i = 0; i < fft.size(); ++i) EXPECT_NEAR(fft[i], brute[i], 1e-4 * (1 + brute[i])) << "copy " << k << " at " << i;
    }
  }
}

// Placements that leave the copy (the window's anchor on it, a margin inside its border): the FFT
// costs equal direct sums (the covered texels' SSD, plus a cost per uncovered one), and the least
// cost is where the window's content came from even with the window hanging off the sample's corner.
TEST(PatchMatching, LeavingPlacementsEqualBruteForceAndFindAPlantedCornerCopy) {
  std::mt19937 rng(testing::SeedFromTestName());
  Image sample = RandomImage(40, 36, 4, rng);
  Image output = RandomImage(50, 45, 4, rng);
  std::vector<uint8_t> synthesized(50 * 45);
  for (auto& s : synthesized) s = rng() % 3 != 0;
  // The output's window (17..27, 23..31) holds the sample from (-2, -2): its top-left 2 x 2 off it.
  for (int y = 2; y < 9; ++y)
    for (int x = 2; x < 11; ++x) std::copy_n(sample.pixel(x - 2, y - 2), 4, output.pixel(17 + x, 23 + y));
  std::vector<RotatedSample> copies;
  for (double r : {0.0, 30.0}) copies.push_back(MakeRotatedSample(sample, Image(), r));
  PatchMatcherOptions options;
  options.max_window = 15;
  options.uncovered_cost = 0.3;
  options.anchor_margin = 1;
  PatchMatcher matcher(copies, options);
  MatchWindow window{11, 9, &output, &synthesized, nullptr, 17, 23};
  window.anchor_x = 6, window.anchor_y = 5;
  for (int k = 0; k < int(copies.size()); ++k) {
    int fw = 0, fh = 0, fu = 0, fv = 0, bw = 0, bh = 0, bu = 0, bv = 0;
    const auto fft = matcher.Costs(window, k, &fw, &fh, &fu, &fv);
    const auto brute = BruteForceLeavingCosts(copies[k], window, options.uncovered_cost, options.anchor_margin, &bw, &bh, &bu, &bv);
    ASSERT_EQ(std::tie(fw, fh, fu, fv), std::tie(bw, bh, bu, bv));
    EXPECT_EQ(fu, 1 - 6);
    EXPECT_EQ(fv, 1 - 5);
    ASSERT_EQ(fft.size(), brute.size());
    for (size_t i = 0; i < fft.size(); ++i) EXPECT_NEAR(fft[i], brute[i], 1e-4 * (1 + brute[i])) << "copy " << k << " at " << i;
  }
  const MatchResult m = matcher.BestMatch(window);
  ASSERT_TRUE(m.found);
  EXPECT_EQ(m.rotation, 0);
  EXPECT_EQ(m.u, -2);
  EXPECT_EQ(m.v, -2);
  double overlap = 0, uncovered = 0;  // the planted copy's only cost: the window's texels off the sample
  for (int y = 0; y < 9; ++y)
    for (int x = 0; x < 11; ++x) {
      const bool s = synthesized[size_t(23 + y) * 50 + 17 + x];
      overlap += s, uncovered += s && (x < 2 || y < 2);
    }
  EXPECT_NEAR(m.cost, options.uncovered_cost * uncovered / overlap, 1e-4);
}

// The matcher correlates each window on the smallest of its planes that keeps the window from
// wrapping onto the copy, by how far the window reaches from its anchor: windows of every reach,
// anchored at their centre or against an edge (quilting clips windows at the output's border),
// cost what direct sums give, on copies of two sizes.
TEST(PatchMatching, LeavingWindowsOfEveryReachEqualBruteForce) {
  std::mt19937 rng(testing::SeedFromTestName());
  const Image sample = RandomImage(40, 36, 3, rng);
  const Image output = RandomImage(60, 60, 3, rng);
  std::vector<uint8_t> synthesized(60 * 60);
  for (auto& s : synthesized) s = rng() % 4 != 0;
  std::vector<RotatedSample> copies;
  for (double r : {0.0, 45.0}) copies.push_back(MakeRotatedSample(sample, Image(), r));
  PatchMatcherOptions options;
  options.max_window = 21;  // reach up to 10: planes for reaches 4, 7 and 10
  options.uncovered_cost = 0.2;
  options.anchor_margin = 4;
  PatchMatcher matcher(copies, options);
  struct Case {
    int width, height, anchor_x, anchor_y;
  };
  for (const Case c : {Case{3, 3, 1, 1}, {9, 9, 4, 4}, {6, 9, 0, 4}, {11, 11, 5, 5}, {8, 15, 7, 7}, {15, 15, 7, 7},
                       {21, 21, 10, 10}, {11, 21, 0, 10}, {11, 11, 10, 0}}) {
    MatchWindow window{c.width, c.height, &output, &synthesized, nullptr, 20, 18};
    window.anchor_x = c.anchor_x, window.anchor_y = c.anchor_y;
    for (int k = 0; k < int(copies.size()); ++k) {
      int fw = 0, fh = 0, fu = 0, fv = 0, bw = 0, bh = 0, bu = 0, bv = 0;
      const auto fft = matcher.Costs(window, k, &fw, &fh, &fu, &fv);
      const auto brute =
          BruteForceLeavingCosts(copies[k], window, options.uncovered_cost, options.anchor_margin, &bw, &bh, &bu, &bv);
      ASSERT_EQ(std::tie(fw, fh, fu, fv), std::tie(bw, bh, bu, bv));
      ASSERT_EQ(fft.size(), brute.size());
      ASSERT_GT(fft.size(), 0u);
      for (size_t i = 0; i < fft.size(); ++i)
        ASSERT_NEAR(fft[i], brute[i], 1e-4 * (1 + brute[i]))
            << c.width << "x" << c.height << " anchored at " << c.anchor_x << "," << c.anchor_y << ", copy " << k << " at " << i;
    }
  }
}

TEST(PatchMatching, FindsAPlantedCopyOfTheSample) {
  std::mt19937 rng(testing::SeedFromTestName());
  const Image sample = RandomImage(48, 48, 3, rng);
  Image output = RandomImage(64, 64, 3, rng);
  std::vector<uint8_t> synthesized(64 * 64, 0);
  // Output texels (20..34, 10..24) hold sample texels (7.., 30..), partly synthesized.
  for (int y = 0; y < 15; ++y)
    for (int x = 0; x < 15; ++x) {
      std::copy_n(sample.pixel(7 + x, 30 - 12 + y), 3, output.pixel(20 + x, 10 + y));
      synthesized[(10 + y) * 64 + 20 + x] = (x + y) % 4 != 0;
    }
  std::vector<RotatedSample> copies{MakeRotatedSample(sample, Image(), 0)};
  PatchMatcher matcher(copies, {});
  const MatchResult m = matcher.BestMatch({15, 15, &output, &synthesized, nullptr, 20, 10});
  ASSERT_TRUE(m.found);
  EXPECT_EQ(m.u, 7);
  EXPECT_EQ(m.v, 18);
  EXPECT_NEAR(m.cost, 0, 1e-4);
}

// A window larger than the sample has no placement: found is false (it once overflowed the FFT
// planes: painting opens a window over a whole target region, which may be larger).
TEST(PatchMatching, AWindowLargerThanEveryCopyIsNotFound) {
  std::mt19937 rng(testing::SeedFromTestName());
  const Image sample = RandomImage(32, 32, 3, rng);
  const Image output = RandomImage(80, 80, 3, rng);
  std::vector<uint8_t> synthesized(80 * 80, 1);
  std::vector<RotatedSample> copies{MakeRotatedSample(sample, Image(), 0)};
  PatchMatcher matcher(copies, {});
  EXPECT_FALSE(matcher.BestMatch({40, 40, &output, &synthesized, nullptr, 5, 5}).found);
  EXPECT_FALSE(matcher.BestMatch({20, 33, &output, &synthesized, nullptr, 5, 5}).found);
  int w = -1, h = -1;
  EXPECT_TRUE(matcher.Costs({40, 40, &output, &synthesized, nullptr, 5, 5}, 0, &w, &h).empty());
  EXPECT_TRUE(matcher.BestMatch({32, 32, &output, &synthesized, nullptr, 5, 5}).found);
}

TEST(PatchMatching, RotatedCopiesStayInsideTheSampleAndTurnTheRightWay) {
  Image sample(33, 33, 2);
  for (int y = 0; y < 33; ++y)
    for (int x = 0; x < 33; ++x) sample.at(x, y, 0) = float(x), sample.at(x, y, 1) = float(y);
  for (double r = 0; r < 360; r += 5) {
    const RotatedSample copy = MakeRotatedSample(sample, Image(), r);
    for (int v = 0; v < copy.size_y; ++v)
      for (int u = 0; u < copy.size_x; ++u) {
        const Eigen::Vector2d s = copy.SourceOf(u, v);
        ASSERT_GE(s.x(), 0) << r;
        ASSERT_LT(s.x(), 33) << r;
        ASSERT_GE(s.y(), 0) << r;
        ASSERT_LT(s.y(), 33) << r;
      }
  }
  // Turned 90 deg counter-clockwise in the material frame (y up the slice): a step right in the
  // copy is a step down the sample's rows.
  const RotatedSample quarter = MakeRotatedSample(sample, Image(), 90);
  EXPECT_EQ(quarter.features.at(5, 5, 1) + 1, quarter.features.at(6, 5, 1));
  EXPECT_EQ(quarter.features.at(5, 5, 0), quarter.features.at(6, 5, 0));
}

}  // namespace
}  // namespace mesocap
