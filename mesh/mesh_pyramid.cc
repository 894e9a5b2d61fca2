#include "mesh/mesh_pyramid.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_simplification/edge_collapse.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Count_ratio_stop_predicate.h>

namespace mesocap {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;

SurfaceMesh ToSurfaceMesh(const TriangleMesh& mesh) {
  std::vector<Point> points;
  points.reserve(mesh.positions.size());
  for (const auto& p : mesh.positions) points.emplace_back(p.x(), p.y(), p.z());
  std::vector<std::vector<std::size_t>> polygons;
  polygons.reserve(mesh.faces.size());
  for (const auto& f : mesh.faces) polygons.push_back({std::size_t(f[0]), std::size_t(f[1]), std::size_t(f[2])});
  // Duplicates vertices where the soup is not a manifold (and orients the faces consistently
  // where it can), so the simplification always has a valid surface mesh.
  CGAL::Polygon_mesh_processing::orient_polygon_soup(points, polygons);
  SurfaceMesh out;
  CGAL::Polygon_mesh_processing::polygon_soup_to_polygon_mesh(points, polygons, out);
  return out;
}

TriangleMesh FromSurfaceMesh(const SurfaceMesh& sm) {
  TriangleMesh mesh;
  std::vector<int32_t> index(sm.number_of_vertices() + sm.number_of_removed_vertices(), -1);
  for (auto v : sm.vertices()) {
    index[v.idx()] = int32_t(mesh.positions.size());
    const Point& p = sm.point(v);
    mesh.positions.emplace_back(p.x(), p.y(), p.z());
  }
  for (auto f : sm.faces()) {
    std::array<int32_t, 3> t{};
    int k = 0;
    for (auto v : CGAL::vertices_around_face(sm.halfedge(f), sm)) {
      if (k < 3) t[k] = index[v.idx()];
      ++k;
    }
    if (k == 3) mesh.faces.push_back(t);
  }
  return mesh;
}

}  // namespace

StatusOr<std::vector<TriangleMesh>> BuildMeshPyramid(const TriangleMesh& mesh, int levels, int min_vertices) {
  std::vector<TriangleMesh> pyramid{mesh};
  if (levels <= 1) return pyramid;
  SurfaceMesh sm = ToSurfaceMesh(mesh);
  for (int l = 1; l < levels; ++l) {
    if (int(sm.number_of_vertices()) / 4 < min_vertices) break;
    namespace SMS = CGAL::Surface_mesh_simplification;
    SMS::Count_ratio_stop_predicate<SurfaceMesh> stop(0.25);
    SMS::edge_collapse(sm, stop);
    sm.collect_garbage();
    TriangleMesh coarse = FromSurfaceMesh(sm);
    MeshRepairReport ignored;
    MESOCAP_RETURN_IF_ERROR(RepairMesh(coarse, &ignored));  // normals from the coarse faces
    pyramid.push_back(std::move(coarse));
  }
  return pyramid;
}

PointGrid::PointGrid(const std::vector<Eigen::Vector3d>& points) : points_(points) {
  Eigen::Vector3d lo = points.empty() ? Eigen::Vector3d::Zero() : points[0], hi = lo;
  for (const auto& p : points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const Eigen::Vector3d extent = (hi - lo).cwiseMax(1e-12);
  // About two points per cell.
  const double volume = extent.prod();
  cell_ = std::cbrt(std::max(volume, 1e-36) * 2.0 / std::max<size_t>(1, points.size()));
  cell_ = std::max(cell_, extent.maxCoeff() / 1024);
  origin_ = lo;
  for (int a = 0; a < 3; ++a) dims_[a] = std::max(1, int(std::ceil(extent[a] / cell_)) + 1);
  const size_t cells = size_t(dims_.x()) * dims_.y() * dims_.z();
  start_.assign(cells + 1, 0);
  std::vector<int32_t> cell_of(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3i c = Cell(points[i]);
    cell_of[i] = int32_t((size_t(c.z()) * dims_.y() + c.y()) * dims_.x() + c.x());
    ++start_[cell_of[i] + 1];
  }
  for (size_t c = 0; c < cells; ++c) start_[c + 1] += start_[c];
  items_.resize(points.size());
  std::vector<int32_t> fill(start_.begin(), start_.end() - 1);
  for (size_t i = 0; i < points.size(); ++i) items_[fill[cell_of[i]]++] = int32_t(i);
}

Eigen::Vector3i PointGrid::Cell(const Eigen::Vector3d& p) const {
  Eigen::Vector3i c;
  for (int a = 0; a < 3; ++a) c[a] = std::clamp(int(std::floor((p[a] - origin_[a]) / cell_)), 0, dims_[a] - 1);
  return c;
}

int PointGrid::Nearest(const Eigen::Vector3d& p) const {
  const Eigen::Vector3i c = Cell(p);
  double best = std::numeric_limits<double>::infinity();
  int best_i = -1;
  // Rings of cells outward until the nearest found cannot be beaten by a farther ring.
  for (int r = 0; r < std::max({dims_.x(), dims_.y(), dims_.z()}); ++r) {
    for (int z = c.z() - r; z <= c.z() + r; ++z)
      for (int y = c.y() - r; y <= c.y() + r; ++y)
        for (int x = c.x() - r; x <= c.x() + r; ++x) {
          if (std::max({std::abs(x - c.x()), std::abs(y - c.y()), std::abs(z - c.z())}) != r) continue;
          if (x < 0 || y < 0 || z < 0 || x >= dims_.x() || y >= dims_.y() || z >= dims_.z()) continue;
          const size_t cell = (size_t(z) * dims_.y() + y) * dims_.x() + x;
          for (int32_t k = start_[cell]; k < start_[cell + 1]; ++k) {
            const double d = (points_[items_[k]] - p).squaredNorm();
            if (d < best) best = d, best_i = items_[k];
          }
        }
    // Any point in ring r + 1 or beyond is at least r cells from p's cell.
    if (best_i >= 0 && std::sqrt(best) <= r * cell_) break;
  }
  return best_i;
}

}  // namespace mesocap
