#include "export/material_preview.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>
#include <numbers>

#include <Eigen/Geometry>

#include "core/parallel.h"
#include "core/pbr_brdf.h"

namespace mesocap {

namespace {

// The material's parameters at texture coordinates (u, v) in [0, 1) (wrapped), nearest texel,
// and the surface normal perturbed by its normal map in the frame (tangent, bitangent, normal).
Eigen::Vector3d Shade(const GgxMaterialMaps& maps, double u, double v, const Eigen::Vector3d& tangent,
                      const Eigen::Vector3d& bitangent, const Eigen::Vector3d& normal, const Eigen::Vector3d& light,
                      const Eigen::Vector3d& view) {
  const int w = maps.base_color.width(), h = maps.base_color.height();
  const int x = std::clamp(int(std::floor((u - std::floor(u)) * w)), 0, w - 1);
  const int y = std::clamp(int(std::floor((v - std::floor(v)) * h)), 0, h - 1);
  const Eigen::Vector3d m(maps.normal.at(x, y, 0), maps.normal.at(x, y, 1), maps.normal.at(x, y, 2));
  const Eigen::Vector3d n = (m.x() * tangent + m.y() * bitangent + m.z() * normal).normalized();
  const Eigen::Vector3d base(maps.base_color.at(x, y, 0), maps.base_color.at(x, y, 1), maps.base_color.at(x, y, 2));
  return PbrReflectance<double>(base, maps.roughness.at(x, y, 0), maps.metallic.at(x, y, 0), n, PbrGeometry(light, view));
}

void Put(Image* image, int x, int y, const Eigen::Vector3d& rgb) {
  for (int c = 0; c < 3; ++c) image->at(x, y, c) = float(rgb[c]);
}

}  // namespace

Image RenderMaterialSphere(const GgxMaterialMaps& maps, const Eigen::Vector3d& light, int size, double repeats) {
  Image out(size, size, 3);
  const Eigen::Vector3d view = Eigen::Vector3d::UnitZ(), l = light.normalized();
  ParallelFor(0, size, [&](int row) {
    for (int col = 0; col < size; ++col) {
      const double x = 2 * (col + 0.5) / size - 1, y = 1 - 2 * (row + 0.5) / size;
      const double r2 = x * x + y * y;
      if (r2 >= 1) continue;
      const Eigen::Vector3d n(x, y, std::sqrt(1 - r2));
      // Longitude around the vertical axis, latitude from the south pole.
      const double longitude = std::atan2(n.x(), n.z()), latitude = std::asin(n.y());
      const double u = repeats * (longitude / (2 * std::numbers::pi) + 0.5), v = repeats * (0.5 - latitude / std::numbers::pi) / 2;
      const Eigen::Vector3d tangent = Eigen::Vector3d(n.z(), 0, -n.x()).normalized();
      const Eigen::Vector3d bitangent = n.cross(tangent);
      Put(&out, col, row, Shade(maps, u, v, tangent, bitangent, n, l, view));
    }
  });
  return out;
}

Image RenderMaterialCloth(const GgxMaterialMaps& maps, const Eigen::Vector3d& light, int size, double repeats) {
  // Height field z(s, t) over the unit square: diagonal folds that fade towards one corner.
  const auto height = [](double s, double t) {
    return 0.06 * std::sin(9 * (s + 0.4 * t)) * (0.4 + 0.6 * t) + 0.03 * std::sin(5 * s - 7 * t);
  };
  const double tilt = 35 * std::numbers::pi / 180;  // the sheet is seen at 35 deg from above
  const Eigen::Vector3d view(0, -std::sin(tilt), std::cos(tilt)), l = light.normalized();
  // Orthographic along -view: the sheet's point (s, t) projects to (s, t cos - z sin); a pixel
  // sees the first t of a 401-step march whose projection reaches its row. Per column, the
  // running maximum of the projection gives every row's first crossing by binary search.
  constexpr int kSteps = 400;
  Image out(size, size, 3);
  ParallelFor(0, size, [&](int col) {
    const double s = (col + 0.5) / size;
    std::vector<double> reached(kSteps + 1);
    double highest = -std::numeric_limits<double>::infinity();
    for (int k = 0; k <= kSteps; ++k) {
      const double t = k / double(kSteps);
      highest = std::max(highest, t * std::cos(tilt) + height(s, t) * std::sin(tilt));
      reached[size_t(k)] = highest;
    }
    for (int row = 0; row < size; ++row) {
      const double target = 1 - (row + 0.5) / size;
      const auto first = std::lower_bound(reached.begin(), reached.end(), target * std::cos(tilt));
      if (first == reached.end()) continue;
      const double t_hit = double(first - reached.begin()) / kSteps;
      const double e = 1e-4;
      const Eigen::Vector3d ds(e, 0, height(s + e, t_hit) - height(s, t_hit)), dt(0, e, height(s, t_hit + e) - height(s, t_hit));
      const Eigen::Vector3d n = ds.cross(dt).normalized();
      const Eigen::Vector3d tangent = ds.normalized(), bitangent = n.cross(tangent);
      Put(&out, col, row, Shade(maps, repeats * s, repeats * (1 - t_hit), tangent, bitangent, n, l, view));
    }
  });
  return out;
}

}  // namespace mesocap
