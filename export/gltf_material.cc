#include "export/gltf_material.h"

#include <cmath>
#include <cstring>
#include <numbers>
#include <tuple>
#include <vector>

#include <tiny_gltf.h>

#include "core/image_io.h"

namespace mesocap {

namespace fs = std::filesystem;

namespace {

using MeshData = GltfMeshGeometry;

void AddVertex(MeshData* m, const Eigen::Vector3f& p, const Eigen::Vector3f& n, const Eigen::Vector3f& t, float u, float v) {
  m->position.insert(m->position.end(), {p.x(), p.y(), p.z()});
  m->normal.insert(m->normal.end(), {n.x(), n.y(), n.z()});
  m->tangent.insert(m->tangent.end(), {t.x(), t.y(), t.z(), 1.0f});
  m->uv.insert(m->uv.end(), {u, v});
}

// A square of side `side` in the x-y plane facing +z; texture x right, y up (glTF v runs down).
MeshData Quad(float side) {
  MeshData m;
  const float h = side / 2;
  for (auto [x, y] : {std::pair{-h, -h}, {h, -h}, {h, h}, {-h, h}})
    AddVertex(&m, {x, y, 0}, {0, 0, 1}, {1, 0, 0}, x / side + 0.5f, 0.5f - y / side);
  m.indices = {0, 1, 2, 0, 2, 3};
  return m;
}

// A UV sphere of `radius`, y up; the texture wraps once around and once from pole to pole.
MeshData Sphere(float radius, int slices = 48, int stacks = 24) {
  MeshData m;
  for (int j = 0; j <= stacks; ++j) {
    const float v = float(j) / stacks, polar = v * float(std::numbers::pi);
    for (int i = 0; i <= slices; ++i) {
      const float u = float(i) / slices, azimuth = u * 2 * float(std::numbers::pi);
      const Eigen::Vector3f n(std::sin(polar) * std::sin(azimuth), std::cos(polar), std::sin(polar) * std::cos(azimuth));
      const Eigen::Vector3f t(std::cos(azimuth), 0, -std::sin(azimuth));  // along increasing u
      AddVertex(&m, radius * n, n, t, u, v);
    }
  }
  for (int j = 0; j < stacks; ++j)
    for (int i = 0; i < slices; ++i) {
      const uint32_t a = uint32_t(j * (slices + 1) + i), b = uint32_t(a + slices + 1);
      m.indices.insert(m.indices.end(), {a, b, a + 1, a + 1, b, b + 1});
    }
  return m;
}

// Appends `bytes` to buffer 0 (4-byte aligned) as a new buffer view; returns its index.
int AddBufferView(tinygltf::Model* model, const void* bytes, size_t size, int target) {
  std::vector<unsigned char>& data = model->buffers[0].data;
  while (data.size() % 4) data.push_back(0);
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = data.size();
  view.byteLength = size;
  view.target = target;
  data.insert(data.end(), static_cast<const unsigned char*>(bytes), static_cast<const unsigned char*>(bytes) + size);
  model->bufferViews.push_back(view);
  return int(model->bufferViews.size()) - 1;
}

int AddFloatAccessor(tinygltf::Model* model, const std::vector<float>& values, int components, int type, bool min_max) {
  tinygltf::Accessor a;
  a.bufferView = AddBufferView(model, values.data(), values.size() * sizeof(float), TINYGLTF_TARGET_ARRAY_BUFFER);
  a.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
  a.count = values.size() / components;
  a.type = type;
  if (min_max) {
    a.minValues.assign(components, 1e30);
    a.maxValues.assign(components, -1e30);
    for (size_t k = 0; k < values.size(); ++k) {
      a.minValues[k % components] = std::min(a.minValues[k % components], double(values[k]));
      a.maxValues[k % components] = std::max(a.maxValues[k % components], double(values[k]));
    }
  }
  model->accessors.push_back(a);
  return int(model->accessors.size()) - 1;
}

int AddMesh(tinygltf::Model* model, const MeshData& data, const std::string& name) {
  tinygltf::Primitive p;
  p.attributes["POSITION"] = AddFloatAccessor(model, data.position, 3, TINYGLTF_TYPE_VEC3, true);
  p.attributes["NORMAL"] = AddFloatAccessor(model, data.normal, 3, TINYGLTF_TYPE_VEC3, false);
  p.attributes["TANGENT"] = AddFloatAccessor(model, data.tangent, 4, TINYGLTF_TYPE_VEC4, false);
  p.attributes["TEXCOORD_0"] = AddFloatAccessor(model, data.uv, 2, TINYGLTF_TYPE_VEC2, false);
  tinygltf::Accessor indices;
  // 16-bit indices when every vertex fits, else 32-bit.
  if (data.position.size() / 3 <= 65535) {
    const std::vector<uint16_t> narrow(data.indices.begin(), data.indices.end());
    indices.bufferView = AddBufferView(model, narrow.data(), narrow.size() * sizeof(uint16_t), TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
    indices.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
  } else {
    indices.bufferView = AddBufferView(model, data.indices.data(), data.indices.size() * sizeof(uint32_t),
                                       TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
    indices.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
  }
  indices.count = data.indices.size();
  indices.type = TINYGLTF_TYPE_SCALAR;
  model->accessors.push_back(indices);
  p.indices = int(model->accessors.size()) - 1;
  p.material = 0;
  p.mode = TINYGLTF_MODE_TRIANGLES;
  tinygltf::Mesh mesh;
  mesh.name = name;
  mesh.primitives.push_back(p);
  model->meshes.push_back(mesh);
  return int(model->meshes.size()) - 1;
}

int AddTexture(tinygltf::Model* model, const std::string& uri) {
  tinygltf::Image image;
  image.uri = uri;
  image.mimeType = "image/png";
  model->images.push_back(image);
  tinygltf::Texture texture;
  texture.source = int(model->images.size()) - 1;
  texture.sampler = 0;
  model->textures.push_back(texture);
  return int(model->textures.size()) - 1;
}

// The textures in glTF's encodings.
Status WriteTextures(const GltfFolder& folder, const GgxMaterialMaps& maps) {
  const int w = maps.base_color.width(), h = maps.base_color.height();
  Image metallic_roughness(w, h, 3), normal(w, h, 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      metallic_roughness.at(x, y, 0) = 1.0f;  // unused (occlusion in packed ORM textures)
      metallic_roughness.at(x, y, 1) = maps.roughness.at(x, y, 0);
      metallic_roughness.at(x, y, 2) = maps.metallic.at(x, y, 0);
      for (int c = 0; c < 3; ++c) normal.at(x, y, c) = 0.5f * (maps.normal.at(x, y, c) + 1.0f);
    }
  MESOCAP_RETURN_IF_ERROR(WriteImage(folder.base_color(), maps.base_color, {.format = PixelFormat::kUint8Srgb}));
  MESOCAP_RETURN_IF_ERROR(WriteImage(folder.metallic_roughness(), metallic_roughness, {.format = PixelFormat::kUint8Linear}));
  return WriteImage(folder.normal(), normal, {.format = PixelFormat::kUint8Linear});
}

}  // namespace

namespace {

// The asset: the textures, one material, and `meshes` as nodes (each with its translation).
Status WriteAsset(const GltfFolder& folder, const GgxMaterialMaps& maps, const GltfMaterialOptions& options,
                  const std::vector<std::tuple<std::string, const MeshData*, std::vector<double>>>& meshes) {
  if (maps.base_color.empty()) return Status::Error("no material to write");
  MESOCAP_RETURN_IF_ERROR(WriteTextures(folder, maps));
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "mesocap";
  model.buffers.resize(1);
  model.buffers[0].uri = GltfFolder::buffer_name();
  tinygltf::Sampler sampler;
  sampler.magFilter = TINYGLTF_TEXTURE_FILTER_LINEAR;
  sampler.minFilter = TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_LINEAR;
  sampler.wrapS = sampler.wrapT = options.tileable ? TINYGLTF_TEXTURE_WRAP_REPEAT : TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE;
  model.samplers.push_back(sampler);
  tinygltf::Material material;
  material.name = options.name;
  material.pbrMetallicRoughness.baseColorTexture.index = AddTexture(&model, GltfFolder::base_color_name());
  material.pbrMetallicRoughness.metallicRoughnessTexture.index = AddTexture(&model, GltfFolder::metallic_roughness_name());
  material.pbrMetallicRoughness.metallicFactor = 1.0;
  material.pbrMetallicRoughness.roughnessFactor = 1.0;
  material.normalTexture.index = AddTexture(&model, GltfFolder::normal_name());
  model.materials.push_back(material);

  tinygltf::Scene scene;
  scene.name = "preview";
  for (const auto& [name, mesh, translation] : meshes) {
    tinygltf::Node node;
    node.name = name;
    node.mesh = AddMesh(&model, *mesh, name);
    node.translation = translation;
    model.nodes.push_back(node);
    scene.nodes.push_back(int(model.nodes.size()) - 1);
  }
  model.scenes.push_back(scene);
  model.defaultScene = 0;

  tinygltf::TinyGLTF writer;
  writer.SetImageWriter(nullptr, nullptr);  // the PNGs are written above; keep their URIs
  const fs::path file = folder.material();
  if (!writer.WriteGltfSceneToFile(&model, file.string(), false, false, true, false))
    return Status::Error(file.string() + ": tinygltf could not write the asset");
  return Status::Ok();
}

}  // namespace

Status WriteGltfMaterial(const GltfFolder& folder, const GgxMaterialMaps& maps, const GltfMaterialOptions& options) {
  const float side = float(options.patch_m);
  const MeshData quad = Quad(side), sphere = Sphere(side / 2);
  return WriteAsset(folder, maps, options, {{"quad", &quad, {-0.6 * side, 0, 0}}, {"sphere", &sphere, {0.6 * side, 0, 0}}});
}

Status WriteGltfMaterialOnMesh(const GltfFolder& folder, const GgxMaterialMaps& maps, const GltfMeshGeometry& mesh,
                               const GltfMaterialOptions& options) {
  if (mesh.position.empty() || mesh.indices.empty()) return Status::Error("no mesh to write");
  return WriteAsset(folder, maps, options, {{"mesh", &mesh, {}}});
}

StatusOr<GgxMaterialMaps> ReadGltfMaterialTextures(const GltfFolder& folder) {
  const fs::path& dir = folder.root;
  auto base = ReadImage(folder.base_color(), {.linearize = true, .max_channels = 3});
  if (!base.ok()) return base.status();
  auto mr = ReadImage(folder.metallic_roughness(), {.linearize = false, .max_channels = 3});
  if (!mr.ok()) return mr.status();
  auto normal = ReadImage(folder.normal(), {.linearize = false, .max_channels = 3});
  if (!normal.ok()) return normal.status();
  const int w = base->width(), h = base->height();
  for (const Image* image : {&*base, &*mr, &*normal})
    if (image->width() != w || image->height() != h || image->channels() != 3)
      return Status::Error(dir.string() + ": the material's textures differ in size or are not RGB");
  GgxMaterialMaps maps;
  maps.base_color = std::move(*base);
  maps.roughness = Image(w, h, 1);
  maps.metallic = Image(w, h, 1);
  maps.normal = Image(w, h, 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      maps.roughness.at(x, y, 0) = mr->at(x, y, 1);
      maps.metallic.at(x, y, 0) = mr->at(x, y, 2);
      Eigen::Vector3f n(2 * normal->at(x, y, 0) - 1, 2 * normal->at(x, y, 1) - 1, 2 * normal->at(x, y, 2) - 1);
      n = n.norm() > 0 ? n.normalized() : Eigen::Vector3f::UnitZ();
      for (int c = 0; c < 3; ++c) maps.normal.at(x, y, c) = n[c];
    }
  return maps;
}

}  // namespace mesocap
