// A dressed mesh on disk (docs/formats.md): `surface_map.ply`, a binary little-endian PLY any mesh
// tool opens, holding the mesh as synthesized (after repair), each vertex's tangent frame and its
// sample coordinate and texton label; for a quilt also each face's corners in the atlas. The
// header's comments name the method, the sample's size, the surface length of one texel and the
// atlas' side. Reading checks every count, index and value and names the file.
#pragma once

#include <filesystem>

#include "core/status.h"
#include "mesh/atlas.h"
#include "mesh/surface_textons.h"
#include "synth/synth_map.h"
#include "mesh/tangent_frames.h"
#include "mesh/triangle_mesh.h"

namespace mesocap {

struct DressedMesh {
  TriangleMesh mesh;
  TangentFrames frames;
  SurfaceMap map;
  // A quilt's atlas (per face its corners' atlas texel coordinates; faces' texcoord property, in
  // [0, 1] of the atlas side) and its per-texel map (atlas_map.exr beside the PLY, read by the
  // caller); empty for per-vertex maps.
  Atlas atlas;
  SynthMap atlas_map;
  bool has_atlas() const { return atlas.size > 0; }
};

Status WriteDressedMesh(const std::filesystem::path& path, const DressedMesh& dressed);
StatusOr<DressedMesh> ReadDressedMesh(const std::filesystem::path& path);

}  // namespace mesocap
