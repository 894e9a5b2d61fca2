// The mesh pyramid of Tong 2002 §5.1's multi-resolution synthesis: each coarser level about a
// quarter of the vertices of the one below, by CGAL's edge-collapse simplification (Lindstrom &
// Turk's cost and placement) in place of Turk's retiling. Non-manifold input is first made
// manifold by CGAL's polygon-soup repair (vertices on a non-manifold edge or fan duplicated).
#pragma once

#include <vector>

#include "core/status.h"
#include "mesh/triangle_mesh.h"

namespace mesocap {

// levels[0] is `mesh` itself; up to `levels` in all, stopping before one would have fewer than
// `min_vertices`.
StatusOr<std::vector<TriangleMesh>> BuildMeshPyramid(const TriangleMesh& mesh, int levels, int min_vertices = 48);

// Nearest-point queries over a fixed set of points (a uniform grid of cells).
class PointGrid {
 public:
  explicit PointGrid(const std::vector<Eigen::Vector3d>& points);
  int Nearest(const Eigen::Vector3d& p) const;  // index of the nearest point

 private:
  Eigen::Vector3i Cell(const Eigen::Vector3d& p) const;
  const std::vector<Eigen::Vector3d>& points_;
  Eigen::Vector3d origin_;
  double cell_ = 1;
  Eigen::Vector3i dims_;
  std::vector<int32_t> start_, items_;
};

}  // namespace mesocap
