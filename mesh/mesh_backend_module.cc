// The mesh backend module (mesh/mesh_backend.h): Assimp reads, Embree casts rays.
#include <cmath>
#include <string>

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <embree3/rtcore.h>

#include "mesh/mesh_backend.h"

namespace mesocap {
namespace {

class EmbreeScene final : public RayScene {
 public:
  explicit EmbreeScene(RTCScene scene) : scene_(scene) {}
  ~EmbreeScene() override { rtcReleaseScene(scene_); }

  RayHit Intersect(const float o[3], const float d[3], float t_far) const override {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit r{};
    SetRay(r.ray, o, d, 0.f, t_far);
    r.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    r.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene_, &context, &r);
    RayHit hit;
    if (r.hit.geomID == RTC_INVALID_GEOMETRY_ID) return hit;
    hit.triangle = int32_t(r.hit.primID), hit.t = r.ray.tfar, hit.u = r.hit.u, hit.v = r.hit.v;
    return hit;
  }

  bool Occluded(const float o[3], const float d[3], float t_near, float t_far) const override {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRay ray{};
    SetRay(ray, o, d, t_near, t_far);
    rtcOccluded1(scene_, &context, &ray);
    return ray.tfar < 0;  // Embree sets tfar to -inf on a hit
  }

 private:
  static void SetRay(RTCRay& ray, const float o[3], const float d[3], float t_near, float t_far) {
    ray.org_x = o[0], ray.org_y = o[1], ray.org_z = o[2];
    ray.dir_x = d[0], ray.dir_y = d[1], ray.dir_z = d[2];
    ray.tnear = t_near, ray.tfar = t_far, ray.mask = 0xFFFFFFFFu, ray.flags = 0, ray.time = 0;
  }

  RTCScene scene_;
};

// One Embree device for the process, made on first use and kept: a device per scene started and
// stopped Embree's worker threads each time (and LeakSanitizer's tracer crashed at exit over them).
RTCDevice Device() {
  static RTCDevice device = rtcNewDevice(nullptr);
  return device;
}

class AssimpEmbreeBackend final : public MeshBackend {
 public:
  StatusOr<MeshFileData> Load(const std::filesystem::path& path) override {
    Assimp::Importer importer;
    // Points and lines are read and dropped (counted); node transforms are baked into the vertices.
    const aiScene* scene = importer.ReadFile(path.string(), aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_PreTransformVertices |
                                                                aiProcess_SortByPType);
    if (!scene || !scene->mRootNode || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE))
      return Status::Error(path.string() + ": not a mesh file mesocap can read (" + importer.GetErrorString() + ")");
    MeshFileData data;
    bool every_mesh_has_normals = true, every_mesh_has_uvs = true;
    for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
      const aiMesh* mesh = scene->mMeshes[m];
      if (!(mesh->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) {
        data.dropped_primitives += int(mesh->mNumFaces);
        continue;
      }
      every_mesh_has_normals = every_mesh_has_normals && mesh->HasNormals();
      every_mesh_has_uvs = every_mesh_has_uvs && mesh->HasTextureCoords(0);
    }
    for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
      const aiMesh* mesh = scene->mMeshes[m];
      if (!(mesh->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
      ++data.meshes;
      const uint32_t base = uint32_t(data.positions.size() / 3);
      for (unsigned i = 0; i < mesh->mNumVertices; ++i) {
        const aiVector3D& p = mesh->mVertices[i];
        data.positions.insert(data.positions.end(), {p.x, p.y, p.z});
        if (every_mesh_has_normals) {
          const aiVector3D& n = mesh->mNormals[i];
          data.normals.insert(data.normals.end(), {n.x, n.y, n.z});
        }
        if (every_mesh_has_uvs) data.uvs.insert(data.uvs.end(), {mesh->mTextureCoords[0][i].x, mesh->mTextureCoords[0][i].y});
      }
      for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
        const aiFace& face = mesh->mFaces[f];
        if (face.mNumIndices != 3) {
          ++data.dropped_primitives;
          continue;
        }
        for (int k = 0; k < 3; ++k) data.triangles.push_back(base + face.mIndices[k]);
      }
    }
    if (data.triangles.empty()) return Status::Error(path.string() + ": the file holds no triangles");
    return data;
  }

  StatusOr<std::unique_ptr<RayScene>> BuildScene(const std::vector<float>& positions,
                                                 const std::vector<uint32_t>& triangles) override {
    RTCDevice device = Device();
    if (!device) return Status::Error("Embree could not start (error " + std::to_string(int(rtcGetDeviceError(nullptr))) + ")");
    RTCScene scene = rtcNewScene(device);
    RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    float* v = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                           3 * sizeof(float), positions.size() / 3));
    unsigned* t = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                 3 * sizeof(unsigned), triangles.size() / 3));
    if (!v || !t) {
      rtcReleaseGeometry(geometry), rtcReleaseScene(scene);
      return Status::Error("Embree could not allocate the scene's buffers");
    }
    std::copy(positions.begin(), positions.end(), v);
    std::copy(triangles.begin(), triangles.end(), t);
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(scene, geometry);
    rtcReleaseGeometry(geometry);
    rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
    rtcCommitScene(scene);
    if (rtcGetDeviceError(device) != RTC_ERROR_NONE) {
      rtcReleaseScene(scene);
      return Status::Error("Embree could not build the scene");
    }
    return std::unique_ptr<RayScene>(new EmbreeScene(scene));
  }
};

}  // namespace
}  // namespace mesocap

extern "C" __attribute__((visibility("default"))) mesocap::MeshBackend* MesocapMeshBackendFactory() {
  static mesocap::AssimpEmbreeBackend backend;
  return &backend;
}
