// A fitted material (export/ggx_fit.h) as a glTF 2.0 asset other tools open: a metallic-
// roughness material with base colour, metallic-roughness and normal textures, on a preview quad
// and sphere, written through tinygltf (Debian's libtinygltf-dev):
//   DIR/material.gltf, material.bin (the meshes), base_color.png (sRGB),
//   metallic_roughness.png (G roughness, B metallic, linear), normal.png (tangent space, linear).
#pragma once

#include <filesystem>
#include <cstdint>
#include <string>
#include <vector>

#include "core/session_layout.h"
#include "core/status.h"
#include "export/ggx_fit.h"

namespace mesocap {

struct GltfMaterialOptions {
  std::string name = "mesocap material";
  double patch_m = 0.064;  // the material's side: the preview quad's size
  bool tileable = false;   // textures repeat (a synthesis map's output); else clamp to the edge
};

// A mesh to carry the material: per vertex a position, a unit normal, a tangent (xyz, then w = +1
// or -1 for the bitangent n x t's sign) and a texture coordinate; triangles.
struct GltfMeshGeometry {
  std::vector<float> position, normal, tangent, uv;  // 3, 3, 4, 2 per vertex
  std::vector<uint32_t> indices;
};

// Writes into `folder` (existing); the caller stages it.
Status WriteGltfMaterial(const GltfFolder& folder, const GgxMaterialMaps& maps, const GltfMaterialOptions& options = {});

// The material on `mesh` (one node "mesh") instead of the preview quad and sphere; indices are
// 16-bit when every vertex fits, else 32-bit.
Status WriteGltfMaterialOnMesh(const GltfFolder& folder, const GgxMaterialMaps& maps, const GltfMeshGeometry& mesh,
                               const GltfMaterialOptions& options = {});

// The textures WriteGltfMaterial wrote, decoded back into maps (8-bit: within half a step of what
// was written; relative_error is left empty).
StatusOr<GgxMaterialMaps> ReadGltfMaterialTextures(const GltfFolder& folder);

}  // namespace mesocap
