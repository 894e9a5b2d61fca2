// Graphcut quilting on a dense atlas mesh (mesh/surface_quilt.h), on meshes written here: a
// UV-less sphere, a torus and a genus-2 surface (atlases of many charts, made by mesh/atlas.h).
// - Every atlas texel inside a chart gets a coordinate inside the sample; patches cross charts.
// - Renders (per pixel through the atlas map) under three lights, from six directions, against a
//   naive planar projection of the sample carried onto the same atlas: over pixel pairs lit and
//   unshadowed with their neighbourhoods and away from silhouettes, the colour step between pixels
//   whose texels lie in different patches or charts over the step inside one: at most 1.2 and below
//   the projection's (whose only cut is its tiling's wrap); the central windows' subband distance
//   to the sample below the projection's.
#include <gtest/gtest.h>

#include <cmath>

#include "mesh/atlas_bake.h"
#include "mesh/mesh_test_support.h"
#include "mesh/surface_quilt.h"
#include "mesh/surface_render.h"
#include "synth/synth_quality.h"
#include "tests/testing.h"

namespace mesocap {
namespace {

constexpr int kSample = 64, kRender = 176, kWindow = 48, kAtlas = 512;

struct Quilted {
  Atlas atlas;
  AtlasTexels texels;
  SynthMap map;
  SurfaceQuiltReport report;
};

Quilted Quilt(const TriangleMesh& mesh, const TangentFrames& frames, const Image& features, int atlas_size, double texel_size) {
  Quilted q;
  auto atlas = BuildAtlas(mesh, {atlas_size, 2});
  EXPECT_TRUE(atlas.ok()) << atlas.status().message();
  q.atlas = std::move(*atlas);
  q.texels = BuildAtlasTexels(mesh, q.atlas);
  SurfaceQuiltOptions o;
  o.seed = testing::SeedFromTestName();
  o.texel_size = texel_size;
  auto map = SurfaceQuiltSynthesis(mesh, frames, q.atlas, q.texels, features, o, &q.report);
  EXPECT_TRUE(map.ok()) << map.status().message();
  q.map = std::move(*map);
  std::printf("%d texels, %d charts, %d patches (%d across charts), %d cuts and %d flattenings refused, seam %.3f of the step, %.1f s\n",
              q.report.texels, q.atlas.charts, q.report.patches, q.report.chart_crossing_patches, q.report.rejected_cuts,
              q.report.rejected_flattenings, q.report.mean_seam_cost / q.report.sample_neighbour_step, q.report.seconds);
  FillAtlasGutter(&q.map, 2);
  return q;
}

TEST(SurfaceQuilt, EveryAtlasTexelGetsAValidCoordinate) {
  const Image sample = testing::PhotoCrop("brick", kSample);
  struct Case {
    const char* name;
    TriangleMesh mesh;
  };
  for (Case& c : std::vector<Case>{{"sphere", testing::IcoSphere(4)}, {"torus", testing::Torus(96, 32)},
                                   {"genus 2", testing::DoubleTorus(48)}}) {
    SCOPED_TRACE(c.name);
    const TangentFrames frames = RelaxedFrames(c.mesh);
    const Quilted q = Quilt(c.mesh, frames, sample, 256, 0);
    EXPECT_GT(q.report.patches, 4);
    EXPECT_GT(q.report.chart_crossing_patches, 0);
    for (int d = 0; d < q.texels.count(); ++d) {
      const size_t i = q.map.index(q.texels.x[d], q.texels.y[d]);
      ASSERT_GE(q.map.patch[i], 0) << "texel " << d;
      ASSERT_TRUE(q.map.source_x[i] >= 0 && q.map.source_x[i] < kSample && q.map.source_y[i] >= 0 && q.map.source_y[i] < kSample);
      ASSERT_TRUE(std::isfinite(q.map.rotation_deg[i]));
    }
  }
}

// The naive planar projection on the atlas: each texel's (x, -y) over the texel size, tiled; its
// rotation the turn of the projection's x axis against the texel's frame.
SynthMap PlanarProjection(const TriangleMesh& mesh, const TangentFrames& frames, const Quilted& q, double texel_size) {
  SynthMap map(q.atlas.size, q.atlas.size, kSample, kSample, "planar");
  for (int d = 0; d < q.texels.count(); ++d) {
    const Eigen::Vector3d& p = q.texels.position[d];
    const double x = std::fmod(std::fmod(p.x() / texel_size, kSample) + kSample, kSample);
    const double y = std::fmod(std::fmod(-p.y() / texel_size, kSample) + kSample, kSample);
    const LocalFrame f = FaceFrame(mesh, frames, q.texels.face[d], q.texels.weights[d].cast<double>());
    const double turn = std::atan2(Eigen::Vector3d::UnitX().dot(f.t), Eigen::Vector3d::UnitX().dot(f.s)) * 180 / M_PI;
    map.Set(q.texels.x[d], q.texels.y[d], float(std::min(x, kSample - 1e-3)), float(std::min(y, kSample - 1e-3)), float(turn),
            d % 2);  // one patch (two ids: the pair test below reads wraps, not ids)
  }
  FillAtlasGutter(&map, 2);
  return map;
}

struct Steps {
  double across = 0, inside = 0;
  long across_pairs = 0, inside_pairs = 0;
  double ratio() const { return (across / across_pairs) / (inside / inside_pairs); }
};

// Whether two pixels' atlas lookups belong to different patches (for the projection: a wrap).
using CutTest = std::function<bool(size_t texel_a, size_t texel_b)>;

void AddSteps(const SurfaceRender& r, const TriangleMesh& mesh, const Atlas& atlas, const RenderCamera& camera, const CutTest& cut,
              Steps* s) {
  const int W = r.width(), H = r.colour.height();
  auto usable = [&](int x, int y) {
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int xx = x + dx, yy = y + dy;
        if (xx < 0 || yy < 0 || xx >= W || yy >= H || !r.lit[size_t(yy) * W + xx]) return false;
      }
    return std::abs(mesh.FaceNormal(r.triangle[size_t(y) * W + x]).dot(camera.RayDirection(x, y))) > 0.3;
  };
  auto texel = [&](size_t i) {
    const auto& uv = atlas.corner_uv[r.triangle[i]];
    const Eigen::Vector2d a = (1 - r.u[i] - r.v[i]) * uv[0] + r.u[i] * uv[1] + r.v[i] * uv[2];
    return size_t(std::floor(a.y())) * atlas.size + size_t(std::floor(a.x()));
  };
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x)
      for (const auto& [dx, dy] : {std::pair{1, 0}, std::pair{0, 1}}) {
        if (x + dx >= W || y + dy >= H || !usable(x, y) || !usable(x + dx, y + dy)) continue;
        double step = 0;
        for (int c = 0; c < 3; ++c) step += std::abs(r.colour.at(x, y, c) - r.colour.at(x + dx, y + dy, c));
        const bool across = cut(texel(size_t(y) * W + x), texel(size_t(y + dy) * W + x + dx));
        (across ? s->across : s->inside) += step;
        ++(across ? s->across_pairs : s->inside_pairs);
      }
}

struct Judged {
  Steps steps;
  double subband = 0;
};

Judged Judge(const TriangleMesh& mesh, const TangentFrames& frames, const Quilted& q, const SynthMap& map, double texel_size,
             const SurfaceAppearance& appearance, const SurfaceScene& scene, const Image& sample_head_on, const CutTest& cut) {
  Judged j;
  for (const Eigen::Vector3d& view : {Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 0),
                                      Eigen::Vector3d(0, 0, -1), Eigen::Vector3d(-1, 0.2, 0), Eigen::Vector3d(0.3, -1, 0)}) {
    const RenderCamera camera = FramingCamera(mesh, kRender, kRender, view);
    const CameraFrame cf = camera.Frame();
    const Eigen::Vector3d back = -cf.forward;
    for (const Eigen::Vector3d& l : {back, Eigen::Vector3d(-0.5 * cf.right + 0.6 * cf.up + 0.6 * back),
                                     Eigen::Vector3d(0.8 * cf.right + 0.2 * cf.up + 0.5 * back)}) {
      RenderLight light;
      light.vector = l.normalized();
      const SurfaceRender r =
          RenderSurface(scene, AtlasShader(appearance, mesh, frames, q.atlas, map, texel_size, camera.eye, light), camera, light);
      AddSteps(r, mesh, q.atlas, camera, cut, &j.steps);
      if (l == back) {  // the central window, head-on light
        Image window(kWindow, kWindow, 3);
        const int o = (kRender - kWindow) / 2;
        for (int y = 0; y < kWindow; ++y)
          for (int x = 0; x < kWindow; ++x)
            for (int c = 0; c < 3; ++c) window.at(x, y, c) = r.colour.at(x + o, y + o, c);
        j.subband += SubbandDistance(window, sample_head_on);
      }
    }
  }
  return j;
}

class SurfaceQuiltQuality : public ::testing::TestWithParam<std::string> {};

TEST_P(SurfaceQuiltQuality, SeamsAndStatisticsBeatAPlanarProjection) {
  const Exemplar e = GetParam() == "rig" ? testing::RigGridBtf("stones", kSample)
                                         : ImageExemplar(testing::PhotoCrop(GetParam(), kSample));
  auto appearance = SurfaceAppearance::FromExemplar(e);
  ASSERT_TRUE(appearance.ok()) << appearance.status().message();
  Image head_on(kSample, kSample, 3);  // the sample as a head-on light and view show it
  for (int y = 0; y < kSample; ++y)
    for (int x = 0; x < kSample; ++x) {
      const Eigen::Vector3f c = appearance->Lookup(x, y, Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitZ());
      for (int k = 0; k < 3; ++k) head_on.at(x, y, k) = c[k];
    }
  const Image features = GetParam() == "rig" ? head_on : e.features;
  const TriangleMesh sphere = testing::IcoSphere(5);
  const TangentFrames frames = RelaxedFrames(sphere);
  const double texel_size = MeanEdgeLength(testing::IcoSphere(6));  // the texton test's scale
  const Quilted q = Quilt(sphere, frames, features, kAtlas, texel_size);
  const SynthMap planar = PlanarProjection(sphere, frames, q, texel_size);
  auto scene = SurfaceScene::Build(sphere);
  ASSERT_TRUE(scene.ok());
  auto chart_of = [&](size_t texel) {
    const int d = q.texels.index[texel];
    return d < 0 ? -1 : q.atlas.face_chart[q.texels.face[d]];
  };
  const Judged quilt = Judge(sphere, frames, q, q.map, texel_size, *appearance, *scene, head_on, [&](size_t a, size_t b) {
    return q.map.patch[a] != q.map.patch[b] || chart_of(a) != chart_of(b);
  });
  const Judged projection = Judge(sphere, frames, q, planar, texel_size, *appearance, *scene, head_on, [&](size_t a, size_t b) {
    return std::abs(planar.source_x[a] - planar.source_x[b]) > kSample / 2 ||
           std::abs(planar.source_y[a] - planar.source_y[b]) > kSample / 2;
  });
  std::printf("%s: seams quilt %.3f (%ld/%ld pairs across/inside), projection %.3f (%ld/%ld); subband quilt %.4f, projection %.4f\n",
              GetParam().c_str(), quilt.steps.ratio(), quilt.steps.across_pairs, quilt.steps.inside_pairs,
              projection.steps.ratio(), projection.steps.across_pairs, projection.steps.inside_pairs, quilt.subband,
              projection.subband);
  EXPECT_LE(quilt.steps.ratio(), 1.2);
  EXPECT_LT(quilt.steps.ratio(), projection.steps.ratio());
  EXPECT_LT(quilt.subband, projection.subband);
}

INSTANTIATE_TEST_SUITE_P(Exemplars, SurfaceQuiltQuality, ::testing::Values("brick", "rig"));

}  // namespace
}  // namespace mesocap
