// Graphcut quilting on a dense atlas mesh (mesh/surface_quilt.h), on meshes written here: a
// UV-less sphere, a torus and a genus-2 surface (atlases of many charts, made by mesh/atlas.h).
// - Every atlas texel inside a chart gets a coordinate inside the sample; patches cross charts.
// - Orientation: with a user field, the texture follows it (planks on a torus, two fields).
// - The mesh's own UVs make the atlas where they form one (a cube-sphere's six charts), and are
//   refused where charts overlap.
// - Renders (per pixel through the atlas map) under three lights, from six directions, against a
//   naive planar projection of the sample carried onto the same atlas: over pixel pairs lit and
//   unshadowed with their neighbourhoods and away from silhouettes, the colour step between pixels
//   whose texels lie in different patches or charts over the step inside one: at most 1.2 and below
//   the projection's (whose only cut is its tiling's wrap); the central windows' subband distance
//   to the sample below the projection's.
#include <gtest/gtest.h>

#include <algorithm>
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

// Quilts on the mesh's own UVs (own_uvs) or on a generated atlas.
Quilted Quilt(const TriangleMesh& mesh, const TangentFrames& frames, const Image& features, int atlas_size, double texel_size,
              bool own_uvs = false) {
  Quilted q;
  auto atlas = own_uvs ? AtlasFromMeshUvs(mesh, {atlas_size, 2}) : BuildAtlas(mesh, {atlas_size, 2});
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

// Orientation: planks (structure-tensor coherence 0.82 on the crop) quilted on a torus's atlas with
// a user field along the tube, then around it. In each of 8 sectors of the torus, the texture's
// dominant orientation in the atlas texels' tangent planes (a structure tensor of the gradients
// fitted over each texel's neighbours, in (s, t)) is the sample's own (in (x, -y)) within 10 deg.
TEST(SurfaceQuilt, TextureOrientationFollowsTheUserField) {
  const Image sample = testing::PhotoCrop("planks", kSample);
  auto luminance = [&](int x, int y) { return testing::SampleLuminance(sample, x, y); };
  const double sample_orientation = testing::SampleOrientation(sample);
  const TriangleMesh torus = testing::Torus(240, 80);
  for (bool along_tube : {true, false}) {
    const DirectionField field = testing::TorusField(along_tube);
    const TangentFrames frames = FieldFrames(torus, field);
    const Quilted q = Quilt(torus, frames, sample, 256, 0);
    std::vector<Eigen::Vector3d> sector(8, Eigen::Vector3d::Zero());  // jss, jtt, jst
    for (int d = 0; d < q.texels.count(); ++d) {
      const LocalFrame f = FaceFrame(torus, frames, q.texels.face[d], q.texels.weights[d].cast<double>());
      const Eigen::Vector2i td = q.map.SourceTexel(q.texels.x[d], q.texels.y[d]);
      Eigen::Matrix2d a = Eigen::Matrix2d::Zero();
      Eigen::Vector2d b = Eigen::Vector2d::Zero();
      for (const int32_t* e = q.texels.neighbours.begin(d); e != q.texels.neighbours.end(d); ++e) {
        const Eigen::Vector3d o = (q.texels.position[*e] - q.texels.position[d]) / q.report.texel_size;
        const Eigen::Vector2d o2(o.dot(f.s), o.dot(f.t));
        const Eigen::Vector2i te = q.map.SourceTexel(q.texels.x[*e], q.texels.y[*e]);
        a += o2 * o2.transpose(), b += o2 * (luminance(te.x(), te.y()) - luminance(td.x(), td.y()));
      }
      if (std::abs(a.determinant()) < 1e-12) continue;
      const Eigen::Vector2d g = a.ldlt().solve(b);
      sector[testing::TorusEighth(q.texels.position[d])] += Eigen::Vector3d(g.x() * g.x(), g.y() * g.y(), g.x() * g.y());
    }
    EXPECT_LT(testing::WorstEighth(sector, sample_orientation, along_tube ? "along the tube" : "around it"), 10.0);
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

// Whether two pixels' atlas texels belong to different patches (for the projection: a wrap).
using CutTest = std::function<bool(size_t texel_a, size_t texel_b)>;

// The atlas texel a render's pixel shows.
size_t PixelTexel(const SurfaceRender& r, const Atlas& atlas, size_t i) {
  const auto& uv = atlas.corner_uv[r.triangle[i]];
  const Eigen::Vector2d a = (1 - r.u[i] - r.v[i]) * uv[0] + r.u[i] * uv[1] + r.v[i] * uv[2];
  return size_t(std::floor(a.y())) * atlas.size + size_t(std::floor(a.x()));
}

struct Judged {
  testing::SeamSteps steps;
  double subband = 0;
};

Judged Judge(const TriangleMesh& mesh, const TangentFrames& frames, const Quilted& q, const SynthMap& map, double texel_size,
             const SurfaceAppearance& appearance, const SurfaceScene& scene, const Image& sample_head_on, const CutTest& cut) {
  Judged j;
  testing::ForSixViewsThreeLights(
      mesh, kRender,
      [&](const RenderCamera& camera, const RenderLight& light) {
        return RenderSurface(scene, AtlasShader(appearance, mesh, frames, q.atlas, map, texel_size, camera.eye, light), camera, light);
      },
      [&](const SurfaceRender& r, const RenderCamera& camera, bool head_on) {
        testing::AddSeamSteps(
            r, mesh, camera, [&](size_t a, size_t b) { return cut(PixelTexel(r, q.atlas, a), PixelTexel(r, q.atlas, b)); },
            &j.steps);
        if (head_on) j.subband += SubbandDistance(testing::CentralWindow(r.colour, kWindow), sample_head_on);
      });
  return j;
}

// The mesh's own UVs make its atlas when they can: six charts of a cube-sphere do; the same
// charts stacked on one square are refused as overlapping.
TEST(SurfaceQuilt, TheMeshsOwnUvsMakeItsAtlasUnlessTheyOverlap) {
  auto own = AtlasFromMeshUvs(testing::CubeSphere(24), {512, 2});
  ASSERT_TRUE(own.ok()) << own.status().message();
  EXPECT_EQ(own->charts, 6);
  EXPECT_GT(own->fill, 0.5);
  auto stacked = AtlasFromMeshUvs(testing::CubeSphere(24, /*stacked=*/true), {512, 2});
  ASSERT_FALSE(stacked.ok());
  EXPECT_NE(stacked.status().message().find("overlap"), std::string::npos) << stacked.status().message();
  EXPECT_FALSE(AtlasFromMeshUvs(testing::IcoSphere(3), {512, 2}).ok());  // no UVs
}

// (exemplar, mesh): the sphere with a generated atlas of 6 charts, the cube-sphere with its own.
class SurfaceQuiltQuality : public ::testing::TestWithParam<std::pair<std::string, std::string>> {};

TEST_P(SurfaceQuiltQuality, SeamsAndStatisticsBeatAPlanarProjection) {
  const std::string name = GetParam().first;
  const bool own_uvs = GetParam().second == "cube-sphere";
  const Exemplar e = name == "rig" ? testing::RigGridBtf("stones", kSample) : ImageExemplar(testing::PhotoCrop(name, kSample));
  auto appearance = SurfaceAppearance::FromExemplar(e);
  ASSERT_TRUE(appearance.ok()) << appearance.status().message();
  const Image head_on = testing::HeadOnSample(*appearance);
  const Image features = name == "rig" ? head_on : e.features;
  const TriangleMesh sphere = own_uvs ? testing::CubeSphere(40) : testing::IcoSphere(5);
  const TangentFrames frames = RelaxedFrames(sphere);
  const double texel_size = MeanEdgeLength(testing::IcoSphere(6));  // the texton test's scale
  const Quilted q = Quilt(sphere, frames, features, kAtlas, texel_size, own_uvs);
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
  std::printf("%s on the %s: seams quilt %.3f (%ld/%ld pairs across/inside), projection %.3f (%ld/%ld); subband quilt %.4f, projection %.4f\n",
              name.c_str(), GetParam().second.c_str(), quilt.steps.ratio(), quilt.steps.across_pairs, quilt.steps.inside_pairs,
              projection.steps.ratio(), projection.steps.across_pairs, projection.steps.inside_pairs, quilt.subband,
              projection.subband);
  EXPECT_LE(quilt.steps.ratio(), 1.2);
  EXPECT_LT(quilt.steps.ratio(), projection.steps.ratio());
  EXPECT_LT(quilt.subband, projection.subband);
}

INSTANTIATE_TEST_SUITE_P(Exemplars, SurfaceQuiltQuality,
                         ::testing::Values(std::pair<std::string, std::string>{"brick", "sphere"},
                                           std::pair<std::string, std::string>{"rig", "sphere"},
                                           std::pair<std::string, std::string>{"brick", "cube-sphere"}));

}  // namespace
}  // namespace mesocap
