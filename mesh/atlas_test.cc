#include "mesh/atlas.h"

#include <gtest/gtest.h>

#include <chrono>

#include "mesh/atlas_bake.h"
#include "mesh/mesh_test_support.h"
#include "tests/testing.h"

namespace mesocap {
namespace {

struct AtlasCase {
  std::string name;
  TriangleMesh (*make)();
};

class Atlases : public ::testing::TestWithParam<AtlasCase> {};

// Every face is in a chart, inside the square and its gutter, unfolded; no texel centre lies
// strictly inside faces of two charts (charts do not overlap); the charts fill a fair share.
TEST_P(Atlases, ChartsAreDisjointUnfoldedAndPacked) {
  const TriangleMesh mesh = GetParam().make();
  const auto start = std::chrono::steady_clock::now();
  auto atlas = BuildAtlas(mesh, {512, 2});
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_TRUE(atlas.ok()) << atlas.status().message();
  std::vector<int32_t> owner(512 * 512, -1);
  long overlaps = 0;
  for (int f = 0; f < mesh.face_count(); ++f) {
    ASSERT_GE(atlas->face_chart[f], 0);
    const auto& uv = atlas->corner_uv[f];
    for (const auto& p : uv) {
      ASSERT_GE(p.minCoeff(), 2 - 1e-6);
      ASSERT_LE(p.maxCoeff(), 510 + 1e-6);
    }
    const Eigen::Vector2d e0 = uv[1] - uv[0], e1 = uv[2] - uv[0];
    const double det = e0.x() * e1.y() - e1.x() * e0.y();
    ASSERT_GT(det, 0) << "face " << f << " is folded or flat in the atlas";
    for (int y = int(std::min({uv[0].y(), uv[1].y(), uv[2].y()})); y <= int(std::max({uv[0].y(), uv[1].y(), uv[2].y()})); ++y)
      for (int x = int(std::min({uv[0].x(), uv[1].x(), uv[2].x()})); x <= int(std::max({uv[0].x(), uv[1].x(), uv[2].x()})); ++x) {
        const Eigen::Vector2d r = Eigen::Vector2d(x + 0.5, y + 0.5) - uv[0];
        const double w1 = (r.x() * e1.y() - e1.x() * r.y()) / det, w2 = (e0.x() * r.y() - r.x() * e0.y()) / det;
        if (w1 <= 1e-6 || w2 <= 1e-6 || 1 - w1 - w2 <= 1e-6) continue;
        int32_t& o = owner[size_t(y) * 512 + x];
        if (o >= 0 && atlas->face_chart[o] != atlas->face_chart[f]) ++overlaps;
        o = f;
      }
  }
  std::printf("%s: %d faces, %d charts, fill %.1f%%, %.2f s\n", GetParam().name.c_str(), mesh.face_count(), atlas->charts,
              100 * atlas->fill, seconds);
  EXPECT_EQ(overlaps, 0);
  EXPECT_GT(atlas->fill, 0.3);
}

TriangleMesh Sphere() { return testing::IcoSphere(5); }
TriangleMesh TorusMesh() { return testing::Torus(120, 40); }
TriangleMesh Genus2() { return testing::DoubleTorus(60); }

INSTANTIATE_TEST_SUITE_P(Meshes, Atlases,
                         ::testing::Values(AtlasCase{"sphere", Sphere}, AtlasCase{"torus", TorusMesh}, AtlasCase{"genus2", Genus2}),
                         [](const auto& info) { return info.param.name; });

}  // namespace
}  // namespace mesocap
