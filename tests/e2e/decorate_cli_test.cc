// decorate and render through the real CLI: a sphere written here dressed from a photograph,
// rendered, and every kind of bad input refused with one line naming the file, exit 1 (2 for a
// bad option), nothing written.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>

#include "core/image_io.h"
#include "core/json.h"
#include "core/session_layout.h"
#include "mesh/surface_map_file.h"
#include "mesh/mesh_test_support.h"
#include "tests/testing.h"

namespace mesocap {
namespace {
namespace fs = std::filesystem;

// A crop of a photograph, written as a PNG.
fs::path WriteSample(const fs::path& dir, int size = 64) {
  const fs::path path = dir / ("sample" + std::to_string(size) + ".png");
  MESOCAP_CHECK(WriteImage(path, testing::PhotoCrop("stones", size)).ok(), "cannot write the sample");
  return path;
}

fs::path WriteMesh(const fs::path& dir) {
  const fs::path path = dir / "sphere.obj";
  MESOCAP_CHECK(WriteObj(path, testing::IcoSphere(4)).ok(), "cannot write the mesh");
  return path;
}

// `mesocap render` of a dressed mesh, 120x90, lit from the front and above.
int RenderFrontLit(const fs::path& map, const fs::path& sample, const fs::path& mesh, const fs::path& png, std::string* log) {
  return testing::RunMesocap("render --map " + map.string() + " --input " + sample.string() + " --mesh " + mesh.string() +
                                 " --light 0,0.5,1 --size 120x90 --no-progress --out " + png.string(),
                             log);
}

TEST(DecorateCli, DressesAMeshAndRendersIt) {
  const fs::path dir = testing::MakeTempDir(), sample = WriteSample(dir), mesh = WriteMesh(dir), out = dir / "dressed";
  std::string log;
  ASSERT_EQ(testing::RunMesocap("decorate --mesh " + mesh.string() + " --input " + sample.string() + " --out " + out.string() +
                                    " --preview-size 96x96 --no-progress",
                                &log),
            0)
      << log;
  const DecorateFolder folder{out};
  for (const fs::path& f : {folder.surface_map(), folder.textons(), folder.report(), folder.preview_light(0), folder.preview_light(1),
                            folder.preview_light(2)})
    EXPECT_TRUE(fs::exists(f)) << f;
  auto dressed = ReadDressedMesh(folder.surface_map());
  ASSERT_TRUE(dressed.ok()) << dressed.status().message();
  EXPECT_EQ(dressed->mesh.vertex_count(), testing::IcoSphere(4).vertex_count());
  auto report = ReadJsonFile(folder.report());
  ASSERT_TRUE(report.ok());
  EXPECT_EQ((*report)["method"], "texton");
  EXPECT_EQ((*report)["quality"]["repeats"].get<double>(), 0.0);
  EXPECT_GT((*report)["previews"][0]["lit_share"].get<double>(), 0.3);

  const fs::path png = dir / "render.png";
  ASSERT_EQ(RenderFrontLit(out, sample, mesh, png, &log), 0) << log;
  auto image = ReadImage(png);
  ASSERT_TRUE(image.ok());
  EXPECT_EQ(image->width(), 120);
  EXPECT_EQ(image->height(), 90);
  ASSERT_EQ(testing::RunMesocap("render --map " + out.string() + " --input " + sample.string() +
                                    " --light-sweep 3 --size 64x64 --no-progress --out " + (dir / "sweep" / "s.png").string(),
                                &log),
            0)
      << log;
  for (const char* f : {"s_0000.png", "s_0001.png", "s_0002.png"}) EXPECT_TRUE(fs::exists(dir / "sweep" / f)) << f;
}

// Quilting on the atlas through the CLI: the per-texel map and the atlas in the PLY, a valid
// glTF asset whose base colour is the sample's colour at the map's texels, and renders through
// the map (render reads the atlas map beside the PLY).
TEST(DecorateCli, QuiltsOnTheAtlasAndRendersIt) {
  const fs::path dir = testing::MakeTempDir(), sample = WriteSample(dir), mesh = dir / "torus.obj", out = dir / "quilted";
  ASSERT_TRUE(WriteObj(mesh, testing::Torus(96, 32)).ok());
  std::string log;
  ASSERT_EQ(testing::RunMesocap("decorate --method quilt --mesh " + mesh.string() + " --input " + sample.string() + " --out " +
                                    out.string() + " --texel-size 0.02 --atlas-size 256 --preview-size 96x96 --no-progress",
                                &log),
            0)
      << log;
  const DecorateFolder folder{out};
  for (const fs::path& f : {folder.surface_map(), folder.atlas_map(), folder.report(), folder.preview_light(0)})
    EXPECT_TRUE(fs::exists(f)) << f;
  EXPECT_FALSE(fs::exists(folder.textons()));
  auto report = ReadJsonFile(folder.report());
  ASSERT_TRUE(report.ok());
  EXPECT_EQ((*report)["method"], "quilt");
  EXPECT_GT((*report)["quality"]["chart_crossing_patches"].get<int>(), 0);
  EXPECT_GT((*report)["previews"][0]["lit_share"].get<double>(), 0.3);
  auto dressed = ReadDressedMesh(folder.surface_map());
  ASSERT_TRUE(dressed.ok()) << dressed.status().message();
  ASSERT_TRUE(dressed->has_atlas());
  EXPECT_EQ(dressed->atlas.size, 256);
  auto map = ReadSynthMap(folder.atlas_map(), /*all_filled=*/false);
  ASSERT_TRUE(map.ok()) << map.status().message();
  ASSERT_EQ(testing::ValidateGltf(folder.gltf().material(), &log), 0) << log;
  // The base colour at every texel inside a face is the sample's colour at the map's texel.
  auto base = ReadImage(folder.gltf().base_color());
  auto photo = ReadImage(sample);
  ASSERT_TRUE(base.ok() && photo.ok());
  long checked = 0;
  for (int f = 0; f < dressed->mesh.face_count(); f += 7) {
    const Eigen::Vector2d centre = (dressed->atlas.corner_uv[f][0] + dressed->atlas.corner_uv[f][1] + dressed->atlas.corner_uv[f][2]) / 3;
    const int x = int(centre.x()), y = int(centre.y());
    if (!map->filled(x, y)) continue;
    const Eigen::Vector2i s = map->SourceTexel(x, y);
    for (int c = 0; c < 3; ++c) ASSERT_NEAR(base->at(x, y, c), photo->at(s.x(), s.y(), c), 1.0 / 255 + 1e-6) << "face " << f;
    ++checked;
  }
  EXPECT_GT(checked, 500);
  const fs::path png = dir / "render.png";
  ASSERT_EQ(RenderFrontLit(out, sample, mesh, png, &log), 0) << log;
  auto image = ReadImage(png);
  ASSERT_TRUE(image.ok());
  double sum = 0;
  for (size_t i = 0; i < image->size(); ++i) sum += image->data()[i];
  EXPECT_GT(sum, 0);
}

// A mesh file's own UVs (OBJ texture coordinates, read by Assimp) make the atlas when they form
// one; overlapping ones are replaced by a generated atlas, and the report says so.
TEST(DecorateCli, UsesTheMeshsOwnUvsOrSaysWhyNot) {
  const fs::path dir = testing::MakeTempDir(), sample = WriteSample(dir);
  for (bool stacked : {false, true}) {
    const fs::path mesh = dir / (stacked ? "stacked.obj" : "charts.obj"), out = dir / (stacked ? "stacked" : "charts");
    ASSERT_TRUE(WriteObj(mesh, testing::CubeSphere(12, stacked)).ok());
    std::string log;
    ASSERT_EQ(testing::RunMesocap("decorate --method quilt --mesh " + mesh.string() + " --input " + sample.string() + " --out " +
                                      out.string() + " --atlas-size 128 --preview-size 32x32 --no-progress",
                                  &log),
              0)
        << log;
    auto report = ReadJsonFile(DecorateFolder{out}.report());
    ASSERT_TRUE(report.ok());
    EXPECT_EQ((*report)["gltf"]["atlas"], stacked ? "generated" : "mesh UVs");
    if (!stacked) {
      EXPECT_EQ((*report)["gltf"]["charts"].get<int>(), 6);
    }
    EXPECT_EQ(log.find("not a usable atlas") != std::string::npos, stacked) << log;
  }
}

// Exit 1 with the file named, and no output folder, for: a mesh with no area, a file that is not
// a mesh, a missing mesh, a field for another mesh, a malformed field; render with another
// exemplar or another mesh; exit 2 for an unknown method.
TEST(DecorateCli, BadInputIsRefusedNamingTheFile) {
  const fs::path dir = testing::MakeTempDir(), sample = WriteSample(dir), mesh = WriteMesh(dir);
  std::ofstream(dir / "flat.obj") << "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n";
  std::ofstream(dir / "notes.ply") << "these are notes, not a mesh\n";
  std::ofstream(dir / "far.json") << R"({"points": [[40, 0, 0]], "directions": [[1, 0, 0]]})";
  std::ofstream(dir / "broken.json") << R"({"points": [[0, 0, 1]], "directions": []})";
  struct Case {
    std::string args, named;
    int code;
  };
  const std::string base = " --input " + sample.string() + " --no-progress --out " + (dir / "out").string();
  for (const Case& c : std::vector<Case>{
           {"--mesh " + (dir / "flat.obj").string() + base, "flat.obj", 1},
           {"--mesh " + (dir / "notes.ply").string() + base, "notes.ply", 1},
           {"--mesh " + (dir / "missing.obj").string() + base, "missing.obj", 1},
           {"--mesh " + mesh.string() + " --field " + (dir / "far.json").string() + base, "far.json", 1},
           {"--mesh " + mesh.string() + " --field " + (dir / "broken.json").string() + base, "broken.json", 1},
           {"--mesh " + mesh.string() + " --method paint" + base, "method", 2},
       }) {
    std::string log;
    EXPECT_EQ(testing::RunMesocap("decorate " + c.args, &log), c.code) << c.args << "\n" << log;
    EXPECT_NE(log.find(c.named), std::string::npos) << log;
    EXPECT_FALSE(fs::exists(dir / "out")) << c.args;
  }
  // A dressed sphere, then render it with another exemplar and against another mesh.
  std::string log;
  ASSERT_EQ(testing::RunMesocap("decorate --mesh " + mesh.string() + " --input " + sample.string() +
                                    " --preview-size 32x32 --no-progress --out " + (dir / "dressed").string(),
                                &log),
            0)
      << log;
  const fs::path other_sample = WriteSample(dir, 48), other_mesh = dir / "torus.obj";
  ASSERT_TRUE(WriteObj(other_mesh, testing::Torus(30, 10)).ok());
  EXPECT_EQ(testing::RunMesocap("render --map " + (dir / "dressed").string() + " --input " + other_sample.string() +
                                    " --size 32x32 --no-progress --out " + (dir / "r1.png").string(),
                                &log),
            1);
  EXPECT_NE(log.find("sample48.png"), std::string::npos) << log;
  EXPECT_EQ(testing::RunMesocap("render --map " + (dir / "dressed").string() + " --input " + sample.string() + " --mesh " +
                                    other_mesh.string() + " --size 32x32 --no-progress --out " + (dir / "r2.png").string(),
                                &log),
            1);
  EXPECT_NE(log.find("torus.obj"), std::string::npos) << log;
  fs::create_directories(dir / "empty");
  EXPECT_EQ(testing::RunMesocap("render --map " + (dir / "empty").string() + " --input " + sample.string() +
                                    " --size 32x32 --no-progress --out " + (dir / "r3.png").string(),
                                &log),
            1);
  EXPECT_NE(log.find("not a folder mesocap decorate wrote"), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(dir / "r1.png") || fs::exists(dir / "r2.png") || fs::exists(dir / "r3.png"));
}

}  // namespace
}  // namespace mesocap

#include <tiny_gltf.h>

namespace mesocap {
namespace {

template <typename T>
const T* AccessorData(const tinygltf::Model& m, int accessor) {
  const auto& a = m.accessors[accessor];
  const auto& v = m.bufferViews[a.bufferView];
  return reinterpret_cast<const T*>(m.buffers[v.buffer].data.data() + v.byteOffset + a.byteOffset);
}

// The glTF asset of a sphere with more vertices than 16-bit indices reach: it validates with no
// error or warning (Khronos' validator), and its base-colour texture is, at texels inside its
// triangles, the sample's colour where the surface map continues from the nearest vertex,
// recomputed here from the asset's own positions, normals, tangents and UVs and the map's file.
TEST(DecorateCli, GltfAssetValidatesAndItsTexturesReproduceTheMap) {
  const fs::path dir = testing::MakeTempDir(), sample = WriteSample(dir), mesh = dir / "big_sphere.obj", out = dir / "dressed";
  ASSERT_TRUE(WriteObj(mesh, testing::IcoSphere(7)).ok());  // 163842 vertices
  std::string log;
  ASSERT_EQ(testing::RunMesocap("decorate --mesh " + mesh.string() + " --input " + sample.string() + " --out " + out.string() +
                                    " --preview-size 64x64 --atlas-size 1024 --no-progress",
                                &log),
            0)
      << log;
  const DecorateFolder folder{out};
  ASSERT_EQ(testing::ValidateGltf(folder.gltf().material(), &log), 0) << log;
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  std::string error, warning;
  ASSERT_TRUE(loader.LoadASCIIFromFile(&model, &error, &warning, folder.gltf().material().string())) << error;
  const auto& primitive = model.meshes.at(0).primitives.at(0);
  EXPECT_EQ(model.accessors[primitive.indices].componentType, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT);
  const float* position = AccessorData<float>(model, primitive.attributes.at("POSITION"));
  const float* normal = AccessorData<float>(model, primitive.attributes.at("NORMAL"));
  const float* tangent = AccessorData<float>(model, primitive.attributes.at("TANGENT"));
  const float* uv = AccessorData<float>(model, primitive.attributes.at("TEXCOORD_0"));
  const uint32_t* indices = AccessorData<uint32_t>(model, primitive.indices);
  const size_t triangles = model.accessors[primitive.indices].count / 3;

  auto dressed = ReadDressedMesh(folder.surface_map());
  ASSERT_TRUE(dressed.ok());
  std::map<std::array<float, 3>, int> by_position;  // the map's vertex at each position
  for (int v = 0; v < dressed->mesh.vertex_count(); ++v) {
    const auto& p = dressed->mesh.positions[v];
    by_position[{float(p.x()), float(p.y()), float(p.z())}] = v;
  }
  ImageReadOptions raw;
  raw.linearize = false;
  auto base = ReadImage(folder.gltf().base_color(), raw);
  auto photo = ReadImage(sample, raw);
  ASSERT_TRUE(base.ok() && photo.ok());
  const int size = base->width();
  long checked = 0, differ = 0;
  for (size_t tri = 0; tri < triangles; tri += 97) {
    Eigen::Vector3d p[3];
    Eigen::Vector2d q[3];
    int vertex[3];
    for (int k = 0; k < 3; ++k) {
      const uint32_t i = indices[3 * tri + k];
      p[k] = Eigen::Vector3d(position[3 * i], position[3 * i + 1], position[3 * i + 2]);
      q[k] = Eigen::Vector2d(uv[2 * i], uv[2 * i + 1]) * size;
      vertex[k] = int(i);
    }
    for (int y = int(std::min({q[0].y(), q[1].y(), q[2].y()})); y <= int(std::max({q[0].y(), q[1].y(), q[2].y()})); ++y)
      for (int x = int(std::min({q[0].x(), q[1].x(), q[2].x()})); x <= int(std::max({q[0].x(), q[1].x(), q[2].x()})); ++x) {
        const Eigen::Vector2d e0 = q[1] - q[0], e1 = q[2] - q[0], r = Eigen::Vector2d(x + 0.5, y + 0.5) - q[0];
        const double det = e0.x() * e1.y() - e1.x() * e0.y();
        const double w1 = (r.x() * e1.y() - e1.x() * r.y()) / det, w2 = (e0.x() * r.y() - r.x() * e0.y()) / det, w0 = 1 - w1 - w2;
        if (w0 < 1e-4 || w1 < 1e-4 || w2 < 1e-4) continue;  // clear of the edges, where two faces share texels
        const Eigen::Vector3d point = w0 * p[0] + w1 * p[1] + w2 * p[2];
        int k = 0;
        for (int j = 1; j < 3; ++j)
          if ((p[j] - point).squaredNorm() < (p[k] - point).squaredNorm()) k = j;
        const uint32_t i = uint32_t(vertex[k]);
        const Eigen::Vector3d n(normal[3 * i], normal[3 * i + 1], normal[3 * i + 2]), s(tangent[4 * i], tangent[4 * i + 1], tangent[4 * i + 2]);
        const int v = by_position.at({float(p[k].x()), float(p[k].y()), float(p[k].z())});
        const Eigen::Vector3d d = (point - p[k]) / dressed->map.texel_size;
        const double sx = dressed->map.source_x[v] + d.dot(s), sy = dressed->map.source_y[v] - d.dot(n.cross(s));
        const int tx = std::clamp(int(std::floor(sx)), 0, 63), ty = std::clamp(int(std::floor(sy)), 0, 63);
        if (std::abs(sx - std::round(sx)) < 1e-3 || std::abs(sy - std::round(sy)) < 1e-3) continue;  // on a texel border: float rounding decides
        ++checked;
        for (int c = 0; c < 3; ++c) differ += std::abs(base->at(x, y, c) - photo->at(tx, ty, c)) > 1.5f / 255;
      }
  }
  std::printf("%ld atlas texels checked, %ld channels differ by more than one 8-bit step\n", checked, differ);
  EXPECT_GT(checked, 2000);
  EXPECT_EQ(differ, 0);
}

}  // namespace
}  // namespace mesocap
