// Surface texton synthesis on a small mesh: fast enough for the sanitizer runs (scripts/sanitize.sh).
#include <gtest/gtest.h>

#include "mesh/surface_textons.h"
#include "mesh/mesh_test_support.h"

namespace mesocap {
namespace {

// The same seed gives the same map whatever the thread count (each sub-pass reads the state it
// began with), and every vertex a coordinate inside the sample.
TEST(SurfaceTextons, SameMapOnOneThreadAndOnAll) {
  const TriangleMesh mesh = testing::IcoSphere(4);
  const TextonAnalysis analysis = testing::AnalyseImage(testing::PhotoCrop("sand", 64));
  const TangentFrames frames = RelaxedFrames(mesh);
  SurfaceTextonOptions o;
  o.num_threads = 1;
  auto one = SurfaceTextonSynthesis(mesh, frames, analysis, o, nullptr);
  o.num_threads = -1;
  auto all = SurfaceTextonSynthesis(mesh, frames, analysis, o, nullptr);
  ASSERT_TRUE(one.ok() && all.ok());
  EXPECT_EQ(one->source_x, all->source_x);
  EXPECT_EQ(one->source_y, all->source_y);
  for (int v = 0; v < mesh.vertex_count(); ++v) {
    ASSERT_GE(one->source_x[v], 0);
    ASSERT_LT(one->source_x[v], 64);
    ASSERT_GE(one->source_y[v], 0);
    ASSERT_LT(one->source_y[v], 64);
  }
}

// Levels and lists made once (as the decorate stage does for several meshes) give each mesh the
// map it gets with its own; levels from another analysis, or with another k, are refused.
TEST(SurfaceTextons, SharedSampleLevelsGiveTheSameMaps) {
  const TextonAnalysis analysis = testing::AnalyseImage(testing::PhotoCrop("sand", 64));
  const TextonAnalysis other = testing::AnalyseImage(testing::PhotoCrop("brick", 64));
  SurfaceTextonOptions o;
  auto shared = MakeSampleLevels(analysis, int(analysis.levels.size()), o.neighbourhood, o.k, -1);
  ASSERT_TRUE(shared.ok());
  for (const TriangleMesh& mesh : {testing::IcoSphere(3), testing::Torus(48, 16)}) {
    const TangentFrames frames = RelaxedFrames(mesh);
    o.sample_levels = nullptr;
    auto own = SurfaceTextonSynthesis(mesh, frames, analysis, o, nullptr);
    o.sample_levels = &*shared;
    auto reused = SurfaceTextonSynthesis(mesh, frames, analysis, o, nullptr);
    ASSERT_TRUE(own.ok() && reused.ok()) << reused.status().message();
    EXPECT_EQ(own->source_x, reused->source_x);
    EXPECT_EQ(own->source_y, reused->source_y);
    EXPECT_FALSE(SurfaceTextonSynthesis(mesh, frames, other, o, nullptr).ok());
    SurfaceTextonOptions other_k = o;
    other_k.k = 5;
    EXPECT_FALSE(SurfaceTextonSynthesis(mesh, frames, analysis, other_k, nullptr).ok());
  }
}

}  // namespace
}  // namespace mesocap
