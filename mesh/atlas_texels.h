// The dense mesh of Zhou 2005 §III-A: the atlas texels inside charts as surface points, one per
// texel, so synthesizing a value per dense vertex is synthesizing a texel of the atlas. Each texel
// knows its face and barycentric weights; its neighbours are the texels beside it in its chart
// and, on a chart's border, the nearby border texels of the other charts (where Zhou zippers the
// charts of his multi-chart geometry image), so patches grow across chart boundaries.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "mesh/atlas.h"
#include "mesh/triangle_mesh.h"

namespace mesocap {

struct AtlasTexels {
  int size = 0;                          // the atlas' side
  std::vector<int32_t> index;            // per atlas texel (row-major): its dense index, or -1
  std::vector<int32_t> x, y, face;       // per dense texel
  std::vector<Eigen::Vector3f> weights;  // per dense texel: barycentric weights of its centre in its face
  std::vector<Eigen::Vector3d> position;
  VertexAdjacency neighbours;            // per dense texel
  double spacing = 0;                    // surface length between neighbouring texels (the atlas' 1 / density)

  int count() const { return int(face.size()); }
  int At(int ax, int ay) const { return ax < 0 || ay < 0 || ax >= size || ay >= size ? -1 : index[size_t(ay) * size + ax]; }
};

// Every texel whose centre lies in a face's atlas triangle (the first face, in face order, where
// triangles touch), then every other texel a face's edge crosses (its weights those of its centre
// in the face's plane, a little outside the face), with their neighbours.
AtlasTexels BuildAtlasTexels(const TriangleMesh& mesh, const Atlas& atlas, int num_threads = -1);

// The barycentric weights of atlas point `uv` in face f's atlas triangle (outside when any is
// negative).
Eigen::Vector3d AtlasWeights(const Atlas& atlas, int f, const Eigen::Vector2d& uv);

}  // namespace mesocap
