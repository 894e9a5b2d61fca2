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

}  // namespace
}  // namespace mesocap
