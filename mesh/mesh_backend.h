// What mesh commands need from heavy libraries, behind an interface whose one implementation lives
// in a module loaded on first use (mesh/mesh_backend_module.cc, libmesocap_mesh_backend.so):
// reading mesh files with Assimp and casting rays with Embree. Every other command starts without
// mapping either (as the image codec keeps OpenImageIO out, core/image_codec.h).
//
// The module holds no state of its own beyond the scenes it builds; errors name the file.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "core/status.h"

namespace mesocap {

// A mesh file's triangles, every mesh of the file in one list with its node transforms applied.
struct MeshFileData {
  std::vector<float> positions;  // 3 per vertex
  std::vector<float> normals;    // 3 per vertex, or empty when the file has none
  std::vector<float> uvs;        // 2 per vertex (the first UV set, v up), or empty unless every mesh has one
  std::vector<uint32_t> triangles;  // 3 per triangle (polygons triangulated, points and lines dropped)
  int meshes = 0;
  int dropped_primitives = 0;    // points and lines in the file
};

struct RayHit {
  int32_t triangle = -1;  // -1: nothing hit
  float t = 0, u = 0, v = 0;  // distance along the ray; barycentrics of vertices 1 and 2
};

// A triangle scene built once; Intersect and Occluded are safe from many threads at once.
class RayScene {
 public:
  virtual ~RayScene() = default;
  virtual RayHit Intersect(const float origin[3], const float direction[3], float t_far) const = 0;
  virtual bool Occluded(const float origin[3], const float direction[3], float t_near, float t_far) const = 0;
};

class MeshBackend {
 public:
  virtual ~MeshBackend() = default;
  virtual StatusOr<MeshFileData> Load(const std::filesystem::path& path) = 0;
  // Positions 3 per vertex, triangles 3 per face (both copied).
  virtual StatusOr<std::unique_ptr<RayScene>> BuildScene(const std::vector<float>& positions,
                                                         const std::vector<uint32_t>& triangles) = 0;
};

inline constexpr const char* kMeshBackendModuleName = "libmesocap_mesh_backend.so";
// The module's one entry point, a MeshBackend* () (core/module_loader.h LoadModuleObject).
inline constexpr const char* kMeshBackendFactorySymbol = "MesocapMeshBackendFactory";

// The backend, loaded once for the process; an error says where the module was looked for.
StatusOr<MeshBackend*> LoadMeshBackend();

}  // namespace mesocap
