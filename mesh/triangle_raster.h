// The grid points inside a triangle of the plane: what the atlas' texels, its UV overlap check and
// surface quilting's work images each rasterise.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>

#include <Eigen/Core>

namespace mesocap {

// The barycentric weights of point q in triangle c (of c[0], c[1], c[2]); (-1, -1, -1) for a
// triangle without area.
inline Eigen::Vector3d Barycentric(const std::array<Eigen::Vector2d, 3>& c, const Eigen::Vector2d& q) {
  const Eigen::Vector2d e0 = c[1] - c[0], e1 = c[2] - c[0], r = q - c[0];
  const double det = e0.x() * e1.y() - e1.x() * e0.y();
  if (std::abs(det) < 1e-18) return Eigen::Vector3d(-1, -1, -1);
  const double w1 = (r.x() * e1.y() - e1.x() * r.y()) / det, w2 = (e0.x() * r.y() - r.x() * e0.y()) / det;
  return {1 - w1 - w2, w1, w2};
}

// visit(x, y, w) for each grid point x in [0, width), y in [row_begin, row_end) whose position
// (x + offset, y + offset) has barycentric weights w in c all at least min_weight.
template <class Visit>
void ForEachGridPointIn(const std::array<Eigen::Vector2d, 3>& c, int width, int row_begin, int row_end, double offset,
                        double min_weight, Visit&& visit) {
  // A box one point wider than the triangle's: a point a rounding error outside may still pass.
  const int x0 = std::max(0, int(std::floor(std::min({c[0].x(), c[1].x(), c[2].x()}) - offset))),
            x1 = std::min(width - 1, int(std::ceil(std::max({c[0].x(), c[1].x(), c[2].x()}) - offset))),
            y0 = std::max(row_begin, int(std::floor(std::min({c[0].y(), c[1].y(), c[2].y()}) - offset))),
            y1 = std::min(row_end - 1, int(std::ceil(std::max({c[0].y(), c[1].y(), c[2].y()}) - offset)));
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) {
      const Eigen::Vector3d w = Barycentric(c, Eigen::Vector2d(x + offset, y + offset));
      if (w.minCoeff() >= min_weight) visit(x, y, w);
    }
}

}  // namespace mesocap
