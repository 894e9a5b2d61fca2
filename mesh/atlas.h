// A texture atlas for a mesh (a multi-chart parameterisation, Zhou 2005 §III's "dense atlas
// mesh"): the faces split into charts, each flattened by least-squares conformal maps (LSCM,
// CGAL), scaled to one texel density and packed into a square. Charts start as connected groups
// of faces whose normals are nearest the same of the six axis directions; a chart that is not a
// topological disk, or whose flattening folds, is cut in two across its longest extent until
// every chart is a disk that flattens without folds.
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>

#include "core/status.h"
#include "mesh/triangle_mesh.h"

namespace mesocap {

struct AtlasOptions {
  int size = 512;    // texels a side
  int gutter = 2;    // empty texels kept around each chart
};

struct Atlas {
  int size = 0;
  std::vector<std::array<Eigen::Vector2d, 3>> corner_uv;  // per face, its corners' atlas texel coordinates
  std::vector<int32_t> face_chart;
  int charts = 0;
  double fill = 0;            // share of the square the charts' triangles cover
  double texels_per_unit = 0; // atlas texels per unit of surface length
};

StatusOr<Atlas> BuildAtlas(const TriangleMesh& mesh, const AtlasOptions& options = {});

// The mesh's own UVs (TriangleMesh::corner_uv, v up) as an atlas of options.size texels (row 0 at
// v = 1), its charts the groups of faces whose UVs join across their edges; an error saying why
// when they do not make one: no UVs, UVs outside [0, 1], a face with no UV area, or charts that
// overlap (a texel inside faces of two places of the surface: tiled or mirrored-and-stacked UVs).
StatusOr<Atlas> AtlasFromMeshUvs(const TriangleMesh& mesh, const AtlasOptions& options = {});

}  // namespace mesocap
