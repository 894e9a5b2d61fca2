#include "mesh/lscm.h"

#include <map>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_parameterization/LSCM_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/parameterize.h>

namespace mesocap {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using SurfaceMesh = CGAL::Surface_mesh<Kernel::Point_3>;
namespace SMP = CGAL::Surface_mesh_parameterization;

std::vector<std::array<Eigen::Vector2d, 3>> FlattenByLscm(const TriangleMesh& m, const std::vector<int32_t>& chart,
                                                          double folded_area_share) {
  if (chart.size() == 1) {  // one triangle: laid flat exactly
    const auto& t = m.faces[chart[0]];
    const Eigen::Vector3d a = m.positions[t[1]] - m.positions[t[0]], b = m.positions[t[2]] - m.positions[t[0]];
    const Eigen::Vector3d x = a.normalized(), y = (b - b.dot(x) * x).normalized();
    return {{Eigen::Vector2d(0, 0), Eigen::Vector2d(a.norm(), 0), Eigen::Vector2d(b.dot(x), b.dot(y))}};
  }
  SurfaceMesh sm;
  std::map<int32_t, SurfaceMesh::Vertex_index> local;
  for (int32_t f : chart)
    for (int32_t v : m.faces[f])
      if (!local.count(v)) local[v] = sm.add_vertex(Kernel::Point_3(m.positions[v].x(), m.positions[v].y(), m.positions[v].z()));
  for (int32_t f : chart) {
    const auto& t = m.faces[f];
    if (sm.add_face(local[t[0]], local[t[1]], local[t[2]]) == SurfaceMesh::null_face()) return {};
  }
  // A disk: Euler characteristic 1 and one border.
  std::vector<SurfaceMesh::Halfedge_index> borders;
  CGAL::Polygon_mesh_processing::extract_boundary_cycles(sm, std::back_inserter(borders));
  if (borders.size() != 1 || int(sm.number_of_vertices()) - int(sm.number_of_edges()) + int(sm.number_of_faces()) != 1) return {};
  auto uv = sm.add_property_map<SurfaceMesh::Vertex_index, Kernel::Point_2>("v:uv").first;
  const auto border = CGAL::Polygon_mesh_processing::longest_border(sm).first;
  if (SMP::parameterize(sm, SMP::LSCM_parameterizer_3<SurfaceMesh>(), border, uv) != SMP::OK) return {};
  std::vector<std::array<Eigen::Vector2d, 3>> out;
  double positive = 0, negative = 0;  // surface area of the faces laid flat either way round
  for (int32_t f : chart) {
    std::array<Eigen::Vector2d, 3> c;
    for (int k = 0; k < 3; ++k) {
      const auto& p = uv[local[m.faces[f][k]]];
      c[k] = Eigen::Vector2d(p.x(), p.y());
      if (!c[k].allFinite()) return {};
    }
    const Eigen::Vector2d a = c[1] - c[0], b = c[2] - c[0];
    const double area = a.x() * b.y() - a.y() * b.x();
    (area > 0 ? positive : negative) += m.FaceArea(f);
    out.push_back(c);
  }
  if (std::min(positive, negative) > folded_area_share * (positive + negative)) return {};  // folded
  if (negative > positive)  // mirrored as a whole
    for (auto& c : out)
      for (auto& p : c) p.x() = -p.x();
  return out;
}

}  // namespace mesocap
