// The dressed mesh as a person sees it: renders of surface texton maps (mesh/surface_textons.h)
// against a naive planar projection of the sample, on a UV-less sphere, from a photograph
// (tests/data/textures/brick) and from the virtual rig's BTF (stones, true values).
// - Seams: over pixel pairs lit and unshadowed on both sides and away from silhouettes, the colour
//   step across patch boundaries (a pixel on a triangle whose texels do not continue each other;
//   for the projection, a triangle across the tiling's wrap) over the step inside patches, under
//   three lights: at most 1.2, and below the projection's.
// - Statistics: the renders' central windows from six directions (head-on light), against the
//   sample seen under the same light: subband distance below the projection's, summed over views.
#include <gtest/gtest.h>

#include <cmath>

#include "capture/material_catalog.h"
#include "capture/true_btf_folder.h"
#include "core/directions.h"
#include "core/image_io.h"
#include "mesh/surface_render.h"
#include "mesh/surface_textons.h"
#include "mesh/mesh_test_support.h"
#include "synth/synth_quality.h"
#include "tests/testing.h"

namespace mesocap {
namespace {

constexpr int kSample = 64, kRender = 176, kWindow = 48;

Exemplar PhotoExemplar(const std::string& name) { return ImageExemplar(testing::PhotoCrop(name, kSample)); }

// The naive planar projection: each vertex's (x, -y) over the texel size, tiled.
SurfaceMap PlanarProjection(const TriangleMesh& mesh, double texel_size, int w, int h) {
  SurfaceMap map;
  map.method = "planar", map.sample_width = w, map.sample_height = h, map.texel_size = texel_size;
  for (const auto& p : mesh.positions) {
    const double x = std::fmod(std::fmod(p.x() / texel_size, w) + w, w), y = std::fmod(std::fmod(-p.y() / texel_size, h) + h, h);
    map.source_x.push_back(float(std::min(x, w - 1e-3))), map.source_y.push_back(float(std::min(y, h - 1e-3)));
    map.label.push_back(-1);
  }
  return map;
}

// Triangles a patch boundary crosses: an edge whose texels do not continue each other (by the edge
// in the first vertex's frame, within one texel).
std::vector<char> CutTriangles(const TriangleMesh& mesh, const TangentFrames& frames, const SurfaceMap& map, bool planar) {
  std::vector<char> cut(mesh.face_count(), 0);
  for (int f = 0; f < mesh.face_count(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = mesh.faces[f][k], b = mesh.faces[f][(k + 1) % 3];
      const Eigen::Vector2d step(map.source_x[b] - map.source_x[a], map.source_y[b] - map.source_y[a]);
      if (planar) {  // the projection is continuous but for the tiling's wrap
        cut[f] |= std::abs(step.x()) > map.sample_width / 2 || std::abs(step.y()) > map.sample_height / 2;
      } else {
        const Eigen::Vector3d d = (mesh.positions[b] - mesh.positions[a]) / map.texel_size;
        cut[f] |= (step - Eigen::Vector2d(d.dot(frames.s[a]), -d.dot(frames.t[a]))).norm() > 1.0;
      }
    }
  return cut;
}

struct Judged {
  testing::SeamSteps steps;
  double subband = 0;
};

Judged Judge(const TriangleMesh& mesh, const TangentFrames& frames, const SurfaceMap& map, const SurfaceAppearance& appearance,
             const SurfaceScene& scene, const Image& sample_head_on, bool planar) {
  Judged j;
  const std::vector<char> cut = CutTriangles(mesh, frames, map, planar);
  testing::ForSixViewsThreeLights(
      mesh, kRender,
      [&](const RenderCamera& camera, const RenderLight& light) {
        return RenderSurface(scene, ShadeVertices(appearance, mesh, frames, map, camera.eye, light), camera, light);
      },
      [&](const SurfaceRender& r, const RenderCamera& camera, bool head_on) {
        testing::AddSeamSteps(r, mesh, camera, [&](size_t a, size_t b) { return cut[r.triangle[a]] || cut[r.triangle[b]]; },
                              &j.steps);
        if (head_on) j.subband += SubbandDistance(testing::CentralWindow(r.colour, kWindow), sample_head_on);
      });
  return j;
}

class SurfaceQuality : public ::testing::TestWithParam<std::string> {};

TEST_P(SurfaceQuality, SeamsAndStatisticsBeatAPlanarProjection) {
  const Exemplar e = GetParam() == "rig" ? testing::RigGridBtf("stones", kSample) : PhotoExemplar(GetParam());
  auto analysis = AnalyzeTextons(AppearanceImageCount(e), [&](int k) { return AppearanceLuminance(e, k); }, {});
  ASSERT_TRUE(analysis.ok()) << analysis.status().message();
  auto appearance = SurfaceAppearance::FromExemplar(e);
  ASSERT_TRUE(appearance.ok()) << appearance.status().message();
  const Image head_on = testing::HeadOnSample(*appearance);
  const TriangleMesh sphere = testing::IcoSphere(6);  // 40962 vertices: one per rendered pixel or more
  const TangentFrames frames = RelaxedFrames(sphere);
  SurfaceTextonOptions o;
  o.seed = testing::SeedFromTestName();
  auto map = SurfaceTextonSynthesis(sphere, frames, *analysis, o, nullptr);
  ASSERT_TRUE(map.ok()) << map.status().message();
  const SurfaceMap planar = PlanarProjection(sphere, map->texel_size, kSample, kSample);
  auto scene = SurfaceScene::Build(sphere);
  ASSERT_TRUE(scene.ok());
  const Judged texton = Judge(sphere, frames, *map, *appearance, *scene, head_on, false);
  const Judged projection = Judge(sphere, frames, planar, *appearance, *scene, head_on, true);
  std::printf("%s: seams texton %.3f (%ld/%ld pairs across/inside), projection %.3f (%ld/%ld); subband texton %.4f, projection %.4f\n",
              GetParam().c_str(), texton.steps.ratio(), texton.steps.across_pairs, texton.steps.inside_pairs,
              projection.steps.ratio(), projection.steps.across_pairs, projection.steps.inside_pairs, texton.subband,
              projection.subband);
  EXPECT_LE(texton.steps.ratio(), 1.2);
  EXPECT_LT(texton.steps.ratio(), projection.steps.ratio());
  EXPECT_LT(texton.subband, projection.subband);
}

INSTANTIATE_TEST_SUITE_P(Exemplars, SurfaceQuality, ::testing::Values("brick", "rig"));

}  // namespace
}  // namespace mesocap
