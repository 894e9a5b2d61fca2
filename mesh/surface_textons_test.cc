// Surface texton maps (mesh/surface_textons.h) on meshes written here: a UV-less sphere, a torus
// and a genus-2 surface with no global parameterisation, from real photographs
// (tests/data/textures).
#include "mesh/surface_textons.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/image_io.h"
#include "mesh/test_meshes.h"
#include "synth/exemplar.h"
#include "tests/testing.h"

namespace mesocap {
namespace {

constexpr int kSample = 64;

Image Crop(const std::string& name, int size = kSample) {
  const auto path = std::filesystem::path(MESOCAP_SOURCE_DIR) / "tests" / "data" / "textures" / (name + ".png");
  auto photo = ReadImage(path, {true, 3});
  MESOCAP_CHECK(photo.ok(), photo.status().message());
  Image crop(size, size, 3);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x)
      for (int c = 0; c < 3; ++c) crop.at(x, y, c) = photo->at(x, y, c);
  return crop;
}

TextonAnalysis Analyse(const Image& sample) {
  const Exemplar e = ImageExemplar(sample);
  auto analysis = AnalyzeTextons(AppearanceImageCount(e), [&](int k) { return AppearanceLuminance(e, k); }, {});
  MESOCAP_CHECK(analysis.ok(), analysis.status().message());
  return std::move(*analysis);
}

struct MeshCase {
  std::string name;
  TriangleMesh (*make)();
};

class SurfaceTextons : public ::testing::TestWithParam<MeshCase> {};

// Every vertex gets a sample coordinate inside the sample with its texel's label; neighbouring
// vertices never copy one texel (no stretched texels) and the map draws on much of the sample.
TEST_P(SurfaceTextons, EveryVertexGetsAValidCoordinateWithoutRepeats) {
  const TriangleMesh mesh = GetParam().make();
  const Image sample = Crop("brick");
  const TextonAnalysis analysis = Analyse(sample);
  const TangentFrames frames = RelaxedFrames(mesh);
  SurfaceTextonOptions o;
  o.seed = testing::SeedFromTestName();
  SurfaceTextonReport report;
  auto map = SurfaceTextonSynthesis(mesh, frames, analysis, o, &report);
  ASSERT_TRUE(map.ok()) << map.status().message();
  ASSERT_EQ(map->size(), mesh.vertex_count());
  for (int v = 0; v < mesh.vertex_count(); ++v) {
    ASSERT_TRUE(map->source_x[v] >= 0 && map->source_x[v] < kSample && map->source_y[v] >= 0 && map->source_y[v] < kSample);
    const Eigen::Vector2i t = map->SourceTexel(v);
    ASSERT_EQ(map->label[v], analysis.levels[0].label(t.x(), t.y()));
  }
  const SurfaceMapUsage f = MeasureSurfaceMap(mesh, frames, *map);
  std::printf("%s: %d vertices, %zu levels, repeats %.2f%%, texels used %.1f%%, coherent edges %.1f%%, "
              "uncovered slots %.2f%%, %.2f s\n",
              GetParam().name.c_str(), mesh.vertex_count(), report.levels.size(), 100 * f.repeats, 100 * f.texels_used,
              100 * f.coherent, 100 * report.levels[0].uncovered_slots, report.seconds);
  EXPECT_LE(f.repeats, 0.02);
  EXPECT_GE(f.texels_used, 0.4);  // the sphere covers 2.5x the sample's area (48% used), the torus 4.7x (80%)
  EXPECT_GE(f.coherent, 0.3);  // patches, not noise: a random map continues ~1 edge in 1000
  EXPECT_GE(report.levels.size(), 3u);
}

TriangleMesh Sphere() { return testing::IcoSphere(5); }                   // 10242 vertices
TriangleMesh TorusMesh() { return testing::Torus(240, 80); }             // 19200 vertices
TriangleMesh Genus2() { return testing::DoubleTorus(110); }

INSTANTIATE_TEST_SUITE_P(Meshes, SurfaceTextons,
                         ::testing::Values(MeshCase{"sphere", Sphere}, MeshCase{"torus", TorusMesh}, MeshCase{"genus2", Genus2}),
                         [](const auto& info) { return info.param.name; });

// The same seed gives the same map whatever the thread count (each sub-pass reads the state it
// began with).
TEST(SurfaceTextons, SameMapOnOneThreadAndOnAll) {
  const TriangleMesh mesh = testing::IcoSphere(4);
  const TextonAnalysis analysis = Analyse(Crop("sand"));
  const TangentFrames frames = RelaxedFrames(mesh);
  SurfaceTextonOptions o;
  o.num_threads = 1;
  auto one = SurfaceTextonSynthesis(mesh, frames, analysis, o, nullptr);
  o.num_threads = -1;
  auto all = SurfaceTextonSynthesis(mesh, frames, analysis, o, nullptr);
  ASSERT_TRUE(one.ok() && all.ok());
  EXPECT_EQ(one->source_x, all->source_x);
  EXPECT_EQ(one->source_y, all->source_y);
}

}  // namespace
}  // namespace mesocap
