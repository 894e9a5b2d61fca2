// decorate and render through the real CLI: a sphere written here dressed from a photograph,
// rendered, and every kind of bad input refused with one line naming the file, exit 1 (2 for a
// bad option), nothing written.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "core/image_io.h"
#include "core/json.h"
#include "core/session_layout.h"
#include "mesh/surface_map_file.h"
#include "mesh/test_meshes.h"
#include "tests/testing.h"

namespace mesocap {
namespace {
namespace fs = std::filesystem;

// A 64-texel crop of a photograph, written as a PNG.
fs::path WriteSample(const fs::path& dir, int size = 64) {
  auto photo = ReadImage(fs::path(MESOCAP_SOURCE_DIR) / "tests" / "data" / "textures" / "stones.png", {true, 3});
  MESOCAP_CHECK(photo.ok(), photo.status().message());
  Image crop(size, size, 3);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x)
      for (int c = 0; c < 3; ++c) crop.at(x, y, c) = photo->at(x, y, c);
  const fs::path path = dir / ("sample" + std::to_string(size) + ".png");
  MESOCAP_CHECK(WriteImage(path, crop).ok(), "cannot write the sample");
  return path;
}

fs::path WriteMesh(const fs::path& dir) {
  const fs::path path = dir / "sphere.obj";
  MESOCAP_CHECK(WriteObj(path, testing::IcoSphere(4)).ok(), "cannot write the mesh");
  return path;
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
  ASSERT_EQ(testing::RunMesocap("render --map " + out.string() + " --input " + sample.string() + " --mesh " + mesh.string() +
                                    " --light 0,0.5,1 --size 120x90 --no-progress --out " + png.string(),
                                &log),
            0)
      << log;
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
  EXPECT_FALSE(fs::exists(dir / "r1.png") || fs::exists(dir / "r2.png"));
}

}  // namespace
}  // namespace mesocap
