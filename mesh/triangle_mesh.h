// A triangle mesh as mesh commands use it: shared vertices (welded by position), per-vertex unit
// normals, and what loading repaired. The file formats are Assimp's (OBJ, PLY, glTF, ...), read
// through the mesh backend module (mesh/mesh_backend.h).
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/status.h"

namespace mesocap {

struct TriangleMesh {
  std::vector<Eigen::Vector3d> positions;
  std::vector<Eigen::Vector3d> normals;  // unit, per vertex
  std::vector<std::array<int32_t, 3>> faces;
  // Per face, its corners' UVs as the file gives them (v up), or empty: a file's UV seams split
  // vertices that welding joins, so they are kept per corner.
  std::vector<std::array<Eigen::Vector2d, 3>> corner_uv;

  int vertex_count() const { return int(positions.size()); }
  int face_count() const { return int(faces.size()); }
  Eigen::Vector3d FaceNormal(int f) const;  // unit (zero for a degenerate face)
  double FaceArea(int f) const;
};

// What RepairMesh changed, each repair standard for its defect.
struct MeshRepairReport {
  int welded_vertices = 0;        // vertices at the same position as another, merged
  int degenerate_faces = 0;       // faces with a repeated vertex or no area, dropped
  int duplicate_faces = 0;        // the same three vertices twice, dropped
  int unreferenced_vertices = 0;  // vertices no face uses, dropped
  int non_manifold_edges = 0;     // edges with more than two faces (kept; reported)
  int dropped_primitives = 0;     // points and lines in the file
  bool normals_recomputed = false;  // missing or unusable normals made from the faces
  std::vector<std::string> Lines() const;  // one line per repair made, for reports
};

// Welds, drops degenerate and duplicate faces and unused vertices, and makes normals from the
// faces (area-weighted) where the mesh has none or some are not unit length. An error when nothing
// with area is left.
Status RepairMesh(TriangleMesh& mesh, MeshRepairReport* report);

// Reads and repairs a mesh file; the error names the file and what is wrong.
StatusOr<TriangleMesh> LoadMesh(const std::filesystem::path& path, MeshRepairReport* report = nullptr);

// A Wavefront OBJ with normals and corner UVs where the mesh has them (the meshes tests write).
Status WriteObj(const std::filesystem::path& path, const TriangleMesh& mesh);

double MeanEdgeLength(const TriangleMesh& mesh);
// The axis-aligned box's diagonal length.
double BoundingDiagonal(const TriangleMesh& mesh);

// Vertex adjacency in compressed rows: the neighbours of v are list[offsets[v] .. offsets[v + 1]).
struct VertexAdjacency {
  std::vector<int32_t> offsets, list;
  int count(int v) const { return offsets[v + 1] - offsets[v]; }
  const int32_t* begin(int v) const { return list.data() + offsets[v]; }
  const int32_t* end(int v) const { return list.data() + offsets[v + 1]; }
};
VertexAdjacency VertexNeighbours(const TriangleMesh& mesh);
VertexAdjacency VertexFaces(const TriangleMesh& mesh);
// Per face, the face across each edge k (corners k, k + 1), or -1: manifold edges only (an edge of
// three faces joins none of them).
std::vector<std::array<int32_t, 3>> FaceNeighbours(const TriangleMesh& mesh);

}  // namespace mesocap
