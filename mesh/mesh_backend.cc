#include "mesh/mesh_backend.h"

#include "core/module_loader.h"

namespace mesocap {

#ifdef MESOCAP_MESH_BACKEND_BUILD_PATH
static constexpr const char* kBuildPath = MESOCAP_MESH_BACKEND_BUILD_PATH;
#else
static constexpr const char* kBuildPath = "";
#endif

StatusOr<MeshBackend*> LoadMeshBackend() {
  static const StatusOr<MeshBackend*> backend =
      LoadModuleObject<MeshBackend>(kMeshBackendModuleName, kBuildPath, kMeshBackendFactorySymbol);
  return backend;
}

}  // namespace mesocap
