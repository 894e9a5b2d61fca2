// The glTF BRDF against closed forms, reciprocity, energy bounds, and its Ceres derivatives
// against finite differences.
#include "core/pbr_brdf.h"

#include <gtest/gtest.h>

#include <ceres/jet.h>

#include <random>

#include "core/directions.h"
#include "tests/testing.h"

namespace mesocap {
namespace {

Eigen::Vector3d RandomUpper(std::mt19937& rng) {
  std::uniform_real_distribution<double> theta(0, 85), phi(0, 360);
  return DirectionFromAnglesDeg(theta(rng), phi(rng));
}

TEST(PbrBrdf, HeadOnMatchesTheClosedForms) {
  const Eigen::Vector3d n = Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d base(0.8, 0.5, 0.2);
  const double roughness = 0.6, a2 = std::pow(roughness, 4);
  // l = v = n: D = 1 / (pi a2), visibility = 1/4, Schlick term 0.
  const double specular = 1 / (4 * std::numbers::pi * a2);
  const Eigen::Vector3d metal = PbrReflectance({base, roughness, 1.0}, n, n, n);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(metal[c], specular * base[c], 1e-12);
  const Eigen::Vector3d dielectric = PbrReflectance({base, roughness, 0.0}, n, n, n);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(dielectric[c], 0.96 * base[c] / std::numbers::pi + 0.04 * specular, 1e-12);
  // Below the horizon: nothing.
  EXPECT_EQ(PbrReflectance({base, roughness, 0.0}, n, -n, n), Eigen::Vector3d::Zero());
}

TEST(PbrBrdf, IsReciprocalAndConservesEnergy) {
  std::mt19937 rng(testing::SeedFromTestName());
  const Eigen::Vector3d n = Eigen::Vector3d::UnitZ();
  for (int k = 0; k < 200; ++k) {
    const PbrMaterial m{Eigen::Vector3d::Random().cwiseAbs(), 0.05 + 0.95 * (k % 10) / 9.0, (k % 5) / 4.0};
    const Eigen::Vector3d l = RandomUpper(rng), v = RandomUpper(rng);
    // BRDF = value / cos(light): symmetric in light and view.
    const Eigen::Vector3d a = PbrReflectance(m, n, l, v) / l.z(), b = PbrReflectance(m, n, v, l) / v.z();
    EXPECT_LT((a - b).norm(), 1e-9 * (1 + a.norm()));
  }
  // Directional albedo of a white material (the integral over views of BRDF x cos(view)) <= 1,
  // by a midpoint rule on the hemisphere. Not for dielectrics at grazing light: glTF's Fresnel mix
  // weighs the diffuse by 1 - F at the half vector, and there reflects up to ~1.2 (measured).
  for (double roughness : {0.2, 0.5, 1.0})
    for (double metallic : {0.0, 1.0})
      for (double theta_i : {0.0, 45.0, 75.0}) {
        if (metallic == 0 && theta_i > 45) continue;
        const PbrMaterial white{Eigen::Vector3d::Ones(), roughness, metallic};
        const Eigen::Vector3d l = DirectionFromAnglesDeg(theta_i, 0);
        const int steps = 400;
        double albedo = 0;
        for (int i = 0; i < steps; ++i)
          for (int j = 0; j < steps; ++j) {
            const double theta = (i + 0.5) / steps * std::numbers::pi / 2, phi = (j + 0.5) / steps * 2 * std::numbers::pi;
            const Eigen::Vector3d v(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
            const double solid_angle = std::sin(theta) * (std::numbers::pi / 2 / steps) * (2 * std::numbers::pi / steps);
            albedo += PbrReflectance(white, n, l, v)[0] / l.z() * v.z() * solid_angle;
          }
        EXPECT_LE(albedo, 1.0 + 1e-3) << roughness << " " << metallic << " " << theta_i;
        EXPECT_GT(albedo, 0.3) << roughness << " " << metallic << " " << theta_i;
      }
}

TEST(PbrBrdf, CeresDerivativesMatchFiniteDifferences) {
  using Jet = ceres::Jet<double, 5>;
  std::mt19937 rng(testing::SeedFromTestName());
  for (int k = 0; k < 50; ++k) {
    const Eigen::Vector3d l = RandomUpper(rng), v = RandomUpper(rng), tilt = 0.2 * Eigen::Vector3d::Random();
    const Eigen::Vector3d n = (Eigen::Vector3d::UnitZ() + Eigen::Vector3d(tilt.x(), tilt.y(), 0)).normalized();
    double p[5] = {0.3 + 0.4 * (k % 3) / 2.0, 0.6, 0.4, 0.2 + 0.7 * (k % 7) / 6.0, (k % 4) / 3.0};  // base, roughness, metallic
    const auto eval = [&](const double* q) {
      return PbrReflectance<double>(Eigen::Vector3d(q[0], q[1], q[2]), q[3], q[4], n, PbrGeometry(l, v));
    };
    Jet jp[5];
    for (int i = 0; i < 5; ++i) jp[i] = Jet(p[i], i);
    const Eigen::Matrix<Jet, 3, 1> f = PbrReflectance<Jet>(Eigen::Matrix<Jet, 3, 1>(jp[0], jp[1], jp[2]), jp[3], jp[4],
                                                           n.cast<Jet>(), PbrGeometry(l, v));
    for (int i = 0; i < 5; ++i) {
      double plus[5], minus[5];
      std::copy(p, p + 5, plus);
      std::copy(p, p + 5, minus);
      const double h = 1e-6;
      plus[i] += h, minus[i] -= h;
      const Eigen::Vector3d numeric = (eval(plus) - eval(minus)) / (2 * h);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(f[c].v[i], numeric[c], 1e-5 * (1 + std::abs(numeric[c]))) << i << " " << c;
    }
  }
}

}  // namespace
}  // namespace mesocap
