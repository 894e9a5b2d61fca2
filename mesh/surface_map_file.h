// A dressed mesh on disk (docs/formats.md): `surface_map.ply`, a binary little-endian PLY any mesh
// tool opens, holding the mesh as synthesized (after repair), each vertex's tangent frame and its
// sample coordinate and texton label. The header's comments name the method, the sample's size and
// the surface length of one texel. Reading checks every count, index and value and names the file.
#pragma once

#include <filesystem>

#include "core/status.h"
#include "mesh/surface_textons.h"
#include "mesh/tangent_frames.h"
#include "mesh/triangle_mesh.h"

namespace mesocap {

struct DressedMesh {
  TriangleMesh mesh;
  TangentFrames frames;
  SurfaceMap map;
};

Status WriteDressedMesh(const std::filesystem::path& path, const DressedMesh& dressed);
StatusOr<DressedMesh> ReadDressedMesh(const std::filesystem::path& path);

}  // namespace mesocap
