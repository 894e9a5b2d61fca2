#include "reconstruct/direction_interpolation.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "core/directions.h"
#include "reconstruct/statistical_btf.h"
#include "tests/testing.h"

namespace mesocap {
namespace {

double WeightSum(const std::vector<WeightedIndex>& w) {
  double s = 0;
  for (const auto& e : w) s += e.weight;
  return s;
}

// The weighted sum of the measured directions' disk points: linear precision of barycentric
// weights means it equals the query inside the hull.
Eigen::Vector2d Blend(const std::vector<WeightedIndex>& w, const std::vector<Eigen::Vector3d>& dirs) {
  Eigen::Vector2d p(0, 0);
  for (const auto& e : w) p += e.weight * dirs[e.index].head<2>();
  return p;
}

TEST(Delaunay, EmptyCircumcirclesOnRandomPoints) {
  std::mt19937 rng(testing::SeedFromTestName());
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Eigen::Vector2d> pts(60);
  for (auto& p : pts) p = {u(rng), u(rng)};
  const auto tris = DelaunayTriangulation(pts);
  // Euler: a triangulation of n points with h on the hull has 2n - 2 - h triangles; at least n.
  EXPECT_GE(tris.size(), pts.size());
  for (const auto& t : tris) {
    const Eigen::Vector2d a = pts[t[0]], b = pts[t[1]], c = pts[t[2]];
    const double d = 2 * (a.x() * (b.y() - c.y()) + b.x() * (c.y() - a.y()) + c.x() * (a.y() - b.y()));
    const Eigen::Vector2d centre((a.squaredNorm() * (b.y() - c.y()) + b.squaredNorm() * (c.y() - a.y()) + c.squaredNorm() * (a.y() - b.y())) / d,
                                 (a.squaredNorm() * (c.x() - b.x()) + b.squaredNorm() * (a.x() - c.x()) + c.squaredNorm() * (b.x() - a.x())) / d);
    const double r = (a - centre).norm();
    for (size_t k = 0; k < pts.size(); ++k)
      if (int(k) != t[0] && int(k) != t[1] && int(k) != t[2]) { EXPECT_GE((pts[k] - centre).norm(), r - 1e-9); }
  }
}

TEST(LightInterpolator, BarycentricWeightsReproduceTheQueryInsideTheHull) {
  const auto dirs = BonnDirections();  // co-circular rings: a degenerate case for Delaunay
  auto interp = LightInterpolator::Create(dirs);
  ASSERT_TRUE(interp.ok()) << interp.status().message();
  std::mt19937 rng(testing::SeedFromTestName());
  // The hull is the outer ring's 24-gon at 75 deg: its edges come in to asin(sin 75 cos 7.5) =
  // 73.3 deg between vertices.
  std::uniform_real_distribution<double> theta(0, 73), phi(0, 360);
  for (int k = 0; k < 200; ++k) {
    const double theta_deg = theta(rng);  // drawn in this order on every compiler
    const Eigen::Vector3d q = DirectionFromAnglesDeg(theta_deg, phi(rng));
    const auto w = interp->Weights(q);
    EXPECT_NEAR(WeightSum(w), 1.0, 1e-9);
    for (const auto& e : w) EXPECT_GE(e.weight, 0.0);
    EXPECT_LT((Blend(w, dirs) - q.head<2>()).norm(), 1e-9);
  }
  // A measured direction gets all the weight.
  const auto exact = interp->Weights(dirs[17]);
  ASSERT_EQ(exact.size(), 1u);
  EXPECT_EQ(exact[0].index, 17);
}

TEST(LightInterpolator, OutsideTheHullProjectsRadiallyOntoIt) {
  std::vector<Eigen::Vector3d> dirs;
  for (int k = 0; k < 6; ++k) dirs.push_back(DirectionFromAnglesDeg(40, 60.0 * k));
  dirs.push_back(Eigen::Vector3d::UnitZ());
  auto interp = LightInterpolator::Create(dirs);
  ASSERT_TRUE(interp.ok());
  const Eigen::Vector3d q = DirectionFromAnglesDeg(80, 30);  // beyond the 40-deg ring, between two lights
  EXPECT_FALSE(interp->Contains(q));
  EXPECT_TRUE(interp->Contains(DirectionFromAnglesDeg(30, 30)));  // hexagon edge at 0.557 on the disk
  const auto w = interp->Weights(q);
  ASSERT_EQ(w.size(), 2u);
  EXPECT_NEAR(w[0].weight, 0.5, 1e-9);
  // The blended point lies on the hull edge, on the ray from the centre through q.
  const Eigen::Vector2d p = Blend(w, dirs);
  EXPECT_NEAR(std::atan2(p.y(), p.x()), std::atan2(q.y(), q.x()), 1e-9);
}

TEST(LightInterpolator, RejectsTooFewDuplicateAndCollinearLights) {
  EXPECT_FALSE(LightInterpolator::Create({Eigen::Vector3d::UnitZ(), DirectionFromAnglesDeg(30, 0)}).ok());
  auto dup = LightInterpolator::Create({Eigen::Vector3d::UnitZ(), DirectionFromAnglesDeg(30, 0), DirectionFromAnglesDeg(30, 0.1),
                                        DirectionFromAnglesDeg(30, 90)});
  ASSERT_FALSE(dup.ok());
  EXPECT_NE(dup.status().message().find("duplicate"), std::string::npos);
  auto line = LightInterpolator::Create({DirectionFromAnglesDeg(30, 0), Eigen::Vector3d::UnitZ(), DirectionFromAnglesDeg(30, 180),
                                         DirectionFromAnglesDeg(60, 0)});
  ASSERT_FALSE(line.ok());
  EXPECT_NE(line.status().message().find("collinear"), std::string::npos);
}

TEST(ViewInterpolator, BilinearInRingsAndExtrapolatesBeyondTheOuterRing) {
  std::vector<Eigen::Vector3d> views = {Eigen::Vector3d::UnitZ()};
  for (int k = 0; k < 4; ++k) views.push_back(DirectionFromAnglesDeg(30, 90.0 * k));
  for (int k = 0; k < 8; ++k) views.push_back(DirectionFromAnglesDeg(60, 45.0 * k));
  auto interp = ViewInterpolator::Create(views);
  ASSERT_TRUE(interp.ok());
  EXPECT_EQ(interp->ring_count(), 3);
  // On a measured view: all weight there.
  auto w = interp->Weights(views[6]);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_EQ(w[0].index, 6);
  // Halfway between the top and the 30-deg view at phi 0.
  w = interp->Weights(DirectionFromAnglesDeg(15, 0));
  ASSERT_EQ(w.size(), 2u);
  EXPECT_NEAR(w[0].weight, 0.5, 1e-9);
  EXPECT_NEAR(w[1].weight, 0.5, 1e-9);
  // Even through the pole: from the top, in 1 - cos(theta); further out unchanged.
  auto even = ViewInterpolator::Create(views, 10.0, 1e9, /*even_at_pole=*/true);
  ASSERT_TRUE(even.ok());
  const double ring_share = (1 - std::cos(DegToRad(15))) / (1 - std::cos(DegToRad(30)));  // 0.2543
  w = even->Weights(DirectionFromAnglesDeg(15, 0));
  ASSERT_EQ(w.size(), 2u);
  EXPECT_EQ(w[0].index, 0);
  EXPECT_NEAR(w[0].weight, 1 - ring_share, 1e-9);
  EXPECT_NEAR(w[1].weight, ring_share, 1e-9);
  EXPECT_NEAR(ring_share, 0.2543, 1e-4);
  for (const double theta : {0.0, 30.0, 45.0, 75.0}) {
    const std::vector<WeightedIndex> linear = interp->Weights(DirectionFromAnglesDeg(theta, 20)),
                                     from_pole = even->Weights(DirectionFromAnglesDeg(theta, 20));
    ASSERT_EQ(linear.size(), from_pole.size()) << theta;
    for (size_t k = 0; k < linear.size(); ++k) EXPECT_NEAR(linear[k].weight, from_pole[k].weight, 1e-9) << theta;
  }
  // 45 deg, phi 45: midway along both rings (30-deg ring between phi 0 and 90), midway in theta.
  w = interp->Weights(DirectionFromAnglesDeg(45, 45));
  EXPECT_NEAR(WeightSum(w), 1.0, 1e-12);
  for (const auto& e : w) {
    if (e.index == 1 || e.index == 2) { EXPECT_NEAR(e.weight, 0.25, 1e-9); }
    if (e.index == 6) { EXPECT_NEAR(e.weight, 0.5, 1e-9); }  // the 60-deg view at phi 45
  }
  // 75 deg extrapolates: weight 1.5 on the 60 ring, -0.5 on the 30 ring.
  w = interp->Weights(DirectionFromAnglesDeg(75, 0));
  EXPECT_NEAR(WeightSum(w), 1.0, 1e-12);
  for (const auto& e : w) {
    if (e.index == 1) { EXPECT_NEAR(e.weight, -0.5, 1e-9); }
    if (e.index == 5) { EXPECT_NEAR(e.weight, 1.5, 1e-9); }
  }
}

}  // namespace
}  // namespace mesocap
