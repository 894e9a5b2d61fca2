// Surface texton maps (mesh/surface_textons.h) on meshes written here: a UV-less sphere, a torus
// and a genus-2 surface with no global parameterisation, from real photographs
// (tests/data/textures).
#include "mesh/surface_textons.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/image_io.h"
#include "mesh/mesh_test_support.h"
#include "synth/exemplar.h"
#include "tests/testing.h"

namespace mesocap {
namespace {

constexpr int kSample = 64;

Image Crop(const std::string& name) { return testing::PhotoCrop(name, kSample); }
TextonAnalysis Analyse(const Image& sample) { return testing::AnalyseImage(sample); }

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

}  // namespace
}  // namespace mesocap

namespace mesocap {
namespace {

// Orientation: planks (a strongly oriented photograph: structure-tensor coherence 0.82 on the
// crop; woodgrain's wavy grain, 0.47, varies by 20 deg across its crop) on a torus with a user field along the
// tube, then around it. In each of 8 sectors of the torus, the synthesized texture's dominant
// orientation in the vertices' tangent planes (a structure tensor of 1-ring gradients, in (s, t))
// is the sample's own (in (x, -y): s runs along the sample's x, t up its rows) within 10 deg.
TEST(SurfaceTextons, TextureOrientationFollowsTheUserField) {
  const Image sample = Crop("planks");
  const TextonAnalysis analysis = Analyse(sample);
  auto luminance = [&](int x, int y) { return testing::SampleLuminance(sample, x, y); };
  const double sample_orientation = testing::SampleOrientation(sample);
  const TriangleMesh torus = testing::Torus(240, 80);
  for (bool along_tube : {true, false}) {
    const DirectionField field = testing::TorusField(along_tube);
    const TangentFrames frames = FieldFrames(torus, field);
    SurfaceTextonOptions o;
    o.seed = testing::SeedFromTestName();
    auto map = SurfaceTextonSynthesis(torus, frames, analysis, o, nullptr);
    ASSERT_TRUE(map.ok()) << map.status().message();
    const VertexAdjacency ring = VertexNeighbours(torus);
    {  // Inside patches the coordinates step with the frame: no turn against it.
      double rot = 0;
      long n = 0;
      for (int v = 0; v < torus.vertex_count(); ++v) {
        Eigen::Matrix2d a = Eigen::Matrix2d::Zero(), b = Eigen::Matrix2d::Zero();
        int m = 0;
        for (const int32_t* u = ring.begin(v); u != ring.end(v); ++u) {
          const Eigen::Vector3d d = (torus.positions[*u] - torus.positions[v]) / map->texel_size;
          const Eigen::Vector2d o2(d.dot(frames.s[v]), -d.dot(frames.t[v]));
          const Eigen::Vector2d c(map->source_x[*u] - map->source_x[v], map->source_y[*u] - map->source_y[v]);
          if ((c - o2).norm() > 1.0) continue;
          a += o2 * o2.transpose(), b += c * o2.transpose(), ++m;
        }
        if (m < 4) continue;
        const Eigen::Matrix2d J = b * a.inverse();
        rot += std::atan2(J(1, 0) - J(0, 1), J(0, 0) + J(1, 1)) * 180 / M_PI, ++n;
      }
      EXPECT_GT(n, torus.vertex_count() / 3);
      EXPECT_LT(std::abs(rot / n), 1.0) << "mean turn of the coordinates against the frames, deg";
    }
    std::vector<Eigen::Vector3d> sector(8, Eigen::Vector3d::Zero());  // jss, jtt, jst
    for (int v = 0; v < torus.vertex_count(); ++v) {
      Eigen::Matrix2d a = Eigen::Matrix2d::Zero();
      Eigen::Vector2d b = Eigen::Vector2d::Zero();
      const Eigen::Vector2i tv = map->SourceTexel(v);
      std::vector<int32_t> near;  // the 2-ring: a wider, more even support than the 1-ring
      for (const int32_t* u = ring.begin(v); u != ring.end(v); ++u)
        for (const int32_t* w = ring.begin(*u); w != ring.end(*u); ++w) near.push_back(*w);
      std::sort(near.begin(), near.end());
      near.erase(std::unique(near.begin(), near.end()), near.end());
      for (int32_t u : near) {
        if (u == v) continue;
        const Eigen::Vector3d d = (torus.positions[u] - torus.positions[v]) / map->texel_size;
        const Eigen::Vector2d o2(d.dot(frames.s[v]), d.dot(frames.t[v]));
        const Eigen::Vector2i tu = map->SourceTexel(u);
        a += o2 * o2.transpose(), b += o2 * (luminance(tu.x(), tu.y()) - luminance(tv.x(), tv.y()));
      }
      const Eigen::Vector2d g = a.ldlt().solve(b);
      sector[testing::TorusEighth(torus.positions[v])] += Eigen::Vector3d(g.x() * g.x(), g.y() * g.y(), g.x() * g.y());
    }
    EXPECT_LT(testing::WorstEighth(sector, sample_orientation, along_tube ? "along the tube" : "around it"), 10.0);
  }
}

}  // namespace
}  // namespace mesocap
