#include "export/material_preview.h"

#include <cmath>
#include <numbers>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "core/pbr_brdf.h"

namespace mesocap {
namespace {

// A uniform material (one colour, roughness and metallic, flat normal map), so that each pixel's
// value depends on the sheet's geometry alone.
GgxMaterialMaps UniformMaps(int size) {
  GgxMaterialMaps maps;
  maps.base_color = Image(size, size, 3);
  maps.roughness = Image(size, size, 1);
  maps.metallic = Image(size, size, 1);
  maps.normal = Image(size, size, 3);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      maps.base_color.at(x, y, 0) = 0.6f, maps.base_color.at(x, y, 1) = 0.4f, maps.base_color.at(x, y, 2) = 0.2f;
      maps.roughness.at(x, y, 0) = 0.4f;
      maps.normal.at(x, y, 2) = 1.0f;
    }
  return maps;
}

// The cloth's pixel by the plain march it is defined by: the first of 401 steps along the sheet
// whose orthographic projection reaches the pixel's row, shaded with the sheet's normal there.
// Returns false where the sheet is not seen.
bool BruteForceClothPixel(const GgxMaterialMaps& maps, const Eigen::Vector3d& light, int size, int col, int row,
                          Eigen::Vector3d* rgb) {
  const auto height = [](double s, double t) {
    return 0.06 * std::sin(9 * (s + 0.4 * t)) * (0.4 + 0.6 * t) + 0.03 * std::sin(5 * s - 7 * t);
  };
  const double tilt = 35 * std::numbers::pi / 180;
  const double s = (col + 0.5) / size, target = 1 - (row + 0.5) / size;
  double t_hit = -1;
  for (int k = 0; k <= 400 && t_hit < 0; ++k) {
    const double t = k / 400.0;
    if (t * std::cos(tilt) + height(s, t) * std::sin(tilt) >= target * std::cos(tilt)) t_hit = t;
  }
  if (t_hit < 0) return false;
  const double e = 1e-4;
  const Eigen::Vector3d ds(e, 0, height(s + e, t_hit) - height(s, t_hit)), dt(0, e, height(s, t_hit + e) - height(s, t_hit));
  const Eigen::Vector3d n = ds.cross(dt).normalized();
  const Eigen::Vector3d view(0, -std::sin(tilt), std::cos(tilt));
  *rgb = PbrReflectance<double>(Eigen::Vector3d(0.6f, 0.4f, 0.2f), double(0.4f), 0.0, n,
                                PbrGeometry(light.normalized(), view));
  return true;
}

TEST(MaterialPreview, TheClothSeesWhatAPlainMarchAlongTheSheetSees) {
  const GgxMaterialMaps maps = UniformMaps(8);
  const Eigen::Vector3d light(0.3, 0.5, 0.8);
  constexpr int kSize = 96;
  const Image cloth = RenderMaterialCloth(maps, light, kSize);
  int seen = 0, empty = 0;
  for (int row = 0; row < kSize; ++row)
    for (int col = 0; col < kSize; ++col) {
      Eigen::Vector3d expected;
      if (!BruteForceClothPixel(maps, light, kSize, col, row, &expected)) {
        ++empty;
        for (int c = 0; c < 3; ++c) EXPECT_EQ(cloth.at(col, row, c), 0.0f) << col << "," << row;
        continue;
      }
      ++seen;
      for (int c = 0; c < 3; ++c) ASSERT_NEAR(cloth.at(col, row, c), expected[c], 1e-6) << col << "," << row << " c" << c;
    }
  // The sheet fills most of the picture and leaves a band above it (seen from 35 deg).
  EXPECT_GT(seen, kSize * kSize / 2);
  EXPECT_GT(empty, 0);
}

}  // namespace
}  // namespace mesocap
