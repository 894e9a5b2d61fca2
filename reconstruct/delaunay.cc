// Delaunay triangulation through CGAL's exact predicates: the light and view rings of a capture
// are co-circular by design, the degenerate case where a floating-point in-circle test decides
// by rounding (a hand-written Bowyer-Watson lost hull triangles that way, depending on the
// compiler), and exact predicates with symbolic perturbation always return a valid one.
#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <algorithm>

#include "reconstruct/direction_interpolation.h"

namespace mesocap {

std::vector<std::array<int, 3>> DelaunayTriangulation(const std::vector<Eigen::Vector2d>& points) {
  using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
  using VertexBase = CGAL::Triangulation_vertex_base_with_info_2<int, Kernel>;
  using Structure = CGAL::Triangulation_data_structure_2<VertexBase>;
  using Triangulation = CGAL::Delaunay_triangulation_2<Kernel, Structure>;
  std::vector<std::pair<Kernel::Point_2, int>> indexed;
  indexed.reserve(points.size());
  for (size_t i = 0; i < points.size(); ++i) indexed.push_back({{points[i].x(), points[i].y()}, int(i)});
  Triangulation triangulation(indexed.begin(), indexed.end());
  // Slivers thinner than rounding (points collinear but for ~1e-17, like sin(180 deg)) would
  // give barycentric weights of 1e16: they are left out, as if the points were collinear.
  Eigen::Vector2d lo = points.empty() ? Eigen::Vector2d::Zero() : points[0], hi = lo;
  for (const auto& p : points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const double min_area = 1e-12 * std::max((hi - lo).squaredNorm(), 1e-300);
  std::vector<std::array<int, 3>> triangles;  // CGAL's faces are counter-clockwise
  for (auto face = triangulation.finite_faces_begin(); face != triangulation.finite_faces_end(); ++face) {
    const std::array<int, 3> t = {face->vertex(0)->info(), face->vertex(1)->info(), face->vertex(2)->info()};
    const Eigen::Vector2d ab = points[t[1]] - points[t[0]], ac = points[t[2]] - points[t[0]];
    if (ab.x() * ac.y() - ab.y() * ac.x() > min_area) triangles.push_back(t);
  }
  // Sorted, so the result does not depend on CGAL's internal face order.
  for (auto& t : triangles) std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
  std::sort(triangles.begin(), triangles.end());
  return triangles;
}

}  // namespace mesocap
