// The renderer (mesh/surface_render.h) against independent references written here: brute-force
// ray casts for visibility and cast shadows, and a lookup of the exemplar's slices for the
// consistency of the mesostructure under any light (per-vertex maps and per-atlas-texel maps).
#include "mesh/surface_render.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "capture/material_catalog.h"
#include "capture/true_btf_folder.h"
#include "core/directions.h"
#include "core/image_io.h"
#include "mesh/atlas_bake.h"
#include "mesh/mesh_test_support.h"
#include "synth/synth_test_support.h"
#include "tests/testing.h"

namespace mesocap {
namespace {

// Möller-Trumbore in double precision over every triangle: the nearest hit's distance and face.
std::pair<double, int> BruteForceHit(const TriangleMesh& m, const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                                     double t_min = 0) {
  double best = std::numeric_limits<double>::infinity();
  int face = -1;
  for (int f = 0; f < m.face_count(); ++f) {
    const Eigen::Vector3d &a = m.positions[m.faces[f][0]], &b = m.positions[m.faces[f][1]], &c = m.positions[m.faces[f][2]];
    const Eigen::Vector3d e1 = b - a, e2 = c - a, p = d.cross(e2);
    const double det = e1.dot(p);
    if (std::abs(det) < 1e-14) continue;
    const Eigen::Vector3d s = o - a;
    const double u = s.dot(p) / det;
    if (u < 0 || u > 1) continue;
    const Eigen::Vector3d q = s.cross(e1);
    const double v = d.dot(q) / det;
    if (v < 0 || u + v > 1) continue;
    const double t = e2.dot(q) / det;
    if (t > t_min && t < best) best = t, face = f;
  }
  return {best, face};
}

// A torus lit from the side: its near half shadows its far half. Every pixel the brute-force
// cast calls occluded is rendered shadowed (black), and every pixel it calls lit is rendered lit,
// except within one pixel of the shadow's edge.
TEST(SurfaceRender, CastShadowsMatchBruteForceRayCasting) {
  const TriangleMesh torus = testing::Torus(64, 24);
  auto scene = SurfaceScene::Build(torus);
  ASSERT_TRUE(scene.ok()) << scene.status().message();
  const RenderCamera camera = FramingCamera(torus, 200, 150, Eigen::Vector3d(0.2, -0.6, 1.0));
  RenderLight light;
  light.vector = Eigen::Vector3d(1, 0, 0.15).normalized();
  const std::vector<Eigen::Vector3f> white(torus.vertex_count(), Eigen::Vector3f::Ones());
  const SurfaceRender r = RenderSurface(*scene, white, camera, light);
  const int W = camera.width, H = camera.height;
  std::vector<int> expected(size_t(W) * H, -1);  // -1 background, 0 dark, 1 lit
  const double eps = 1e-5 * BoundingDiagonal(torus);
  long occluded = 0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const Eigen::Vector3d d = camera.RayDirection(x, y);
      const auto [t, f] = BruteForceHit(torus, camera.eye, d);
      if (f < 0) continue;
      const Eigen::Vector3d p = camera.eye + t * d;
      Eigen::Vector3d n = torus.FaceNormal(f);
      if (n.dot(d) > 0) n = -n;
      const Eigen::Vector3d l = light.DirectionFrom(p);
      bool lit = n.dot(l) > 0;
      if (lit) {
        lit = BruteForceHit(torus, p + eps * n, l).second < 0;
        occluded += !lit;
      }
      expected[size_t(y) * W + x] = lit;
    }
  ASSERT_GT(occluded, 200) << "the light must cast a shadow of the torus on itself";
  long mismatched = 0, compared = 0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const size_t i = size_t(y) * W + x;
      const int rendered = r.triangle[i] < 0 ? -1 : r.lit[i];
      if (expected[i] < 0 && rendered < 0) continue;
      bool edge = false;  // the brute force's state changes within one pixel
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int xx = std::clamp(x + dx, 0, W - 1), yy = std::clamp(y + dy, 0, H - 1);
          edge = edge || expected[size_t(yy) * W + xx] != expected[i];
        }
      if (edge) continue;
      ++compared;
      if (rendered != expected[i]) ++mismatched;
      if (rendered == 0) {
        EXPECT_EQ(r.colour.at(x, y, 0), 0.f);
      } else if (rendered == 1) {
        EXPECT_GT(r.colour.at(x, y, 0), 0.f);
      }
    }
  std::printf("%ld pixels compared away from edges, %ld occluded by brute force, %ld differ\n", compared, occluded, mismatched);
  EXPECT_GT(compared, 3000);
  EXPECT_EQ(mismatched, 0);
}

// The independent lookup: the slices read from disk, the 4 nearest views by angle and the 4
// nearest lights of each, inverse-angle weights (docs: mesh/surface_shading.h).
Eigen::Vector3f ReferenceLookup(const Exemplar& e, const std::vector<Image>& slices, int x, int y, const Eigen::Vector3d& l,
                                const Eigen::Vector3d& v) {
  if (l.z() <= 0) return Eigen::Vector3f::Zero();
  auto angle = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) { return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)); };
  std::vector<Eigen::Vector3d> views;
  for (const auto& s : e.slices) {
    bool known = false;
    for (const auto& w : views) known = known || angle(w, s.view) < 1e-6;
    if (!known) views.push_back(s.view);
  }
  std::sort(views.begin(), views.end(), [&](const auto& a, const auto& b) { return angle(a, v) < angle(b, v); });
  views.resize(std::min<size_t>(4, views.size()));
  double view_sum = 0;
  for (const auto& w : views) view_sum += 1 / (angle(w, v) + 0.01);
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const auto& w : views) {
    std::vector<int> of_view;
    for (size_t k = 0; k < e.slices.size(); ++k)
      if (angle(e.slices[k].view, w) < 1e-6) of_view.push_back(int(k));
    std::sort(of_view.begin(), of_view.end(), [&](int a, int b) { return angle(e.slices[a].light, l) < angle(e.slices[b].light, l); });
    of_view.resize(std::min<size_t>(4, of_view.size()));
    double light_sum = 0;
    for (int k : of_view) light_sum += 1 / (angle(e.slices[k].light, l) + 0.01);
    for (int k : of_view) {
      const double weight = (1 / (angle(w, v) + 0.01) / view_sum) * (1 / (angle(e.slices[k].light, l) + 0.01) / light_sum);
      for (int ch = 0; ch < 3; ++ch) c[ch] += weight * slices[k].at(x, y, ch);
    }
  }
  return c.cast<float>();
}

// What both lookup tests compare: the rig's stones BTF (32 texels) with its slices read whole, and
// a torus with a relaxed field.
struct RigOnTorus {
  Exemplar btf;
  std::vector<Image> slices;
  SurfaceAppearance appearance;
  TriangleMesh torus;
  TangentFrames frames;
};

RigOnTorus MakeRigOnTorus() {
  RigOnTorus r;
  r.btf = testing::RigGridBtf("stones", 32);
  for (size_t k = 0; k < r.btf.slices.size(); ++k) r.slices.push_back(*r.btf.ReadSlice(int(k)));
  auto appearance = SurfaceAppearance::FromExemplar(r.btf);
  MESOCAP_CHECK(appearance.ok(), appearance.status().message());
  r.appearance = std::move(*appearance);
  r.torus = testing::Torus(120, 40);
  r.frames = RelaxedFrames(r.torus);
  return r;
}

// Consistent mesostructure: at sampled lit vertices under several lights the rendered value is the
// exemplar's BTF at the vertex's mapped texel and local directions; every lit pixel is the blend
// of its triangle's vertex values.
TEST(SurfaceRender, RenderedValuesAreTheExemplarsAtTheMappedCoordinates) {
  const auto [btf, slices, appearance, torus, frames] = MakeRigOnTorus();
  SurfaceMap map;  // any map: here a deterministic scatter of texels
  map.sample_width = map.sample_height = 32, map.texel_size = MeanEdgeLength(torus);
  for (int v = 0; v < torus.vertex_count(); ++v)
    map.source_x.push_back(float((v * 7) % 32) + 0.5f), map.source_y.push_back(float((v * 13 / 5) % 32) + 0.5f), map.label.push_back(-1);
  auto scene = SurfaceScene::Build(torus);
  ASSERT_TRUE(scene.ok());
  const RenderCamera camera = FramingCamera(torus, 160, 120);
  long checked = 0;
  for (const Eigen::Vector3d& to_light : {Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(1, 0.3, 0.6), Eigen::Vector3d(-0.5, 0.8, 0.4)}) {
    RenderLight light;
    light.vector = to_light.normalized();
    const auto colours = ShadeVertices(appearance, torus, frames, map, camera.eye, light);
    for (int v = 0; v < torus.vertex_count(); v += 11) {
      const Eigen::Vector3d& p = torus.positions[v];
      const Eigen::Vector3d l = frames.ToLocal(v, light.vector), w = frames.ToLocal(v, (camera.eye - p).normalized());
      const Eigen::Vector2i t = map.SourceTexel(v);
      const Eigen::Vector3f ref = ReferenceLookup(btf, slices, t.x(), t.y(), l, w);
      for (int c = 0; c < 3; ++c) ASSERT_NEAR(colours[v][c], ref[c], 1.0 / 255) << "vertex " << v;
      checked += l.z() > 0;
    }
    const SurfaceRender r = RenderSurface(*scene, colours, camera, light);
    for (size_t i = 0; i < r.lit.size(); ++i) {
      if (!r.lit[i]) continue;
      const auto& f = torus.faces[r.triangle[i]];
      const Eigen::Vector3f blend = (1 - r.u[i] - r.v[i]) * colours[f[0]] + r.u[i] * colours[f[1]] + r.v[i] * colours[f[2]];
      const int x = int(i % 160), y = int(i / 160);
      for (int c = 0; c < 3; ++c) ASSERT_NEAR(r.colour.at(x, y, c), blend[c], 1e-5);
    }
  }
  EXPECT_GT(checked, 300);
}

// The same for a per-atlas-texel map (a quilt's): at sampled lit pixels the rendered value is the
// exemplar's BTF at the sample texel the pixel's atlas texel names and the light and view in the
// frame at the pixel's point, turned by the texel's rotation, all recomputed here.
TEST(SurfaceRender, AtlasMapPixelsAreTheExemplarsAtTheMappedCoordinates) {
  const auto [btf, slices, appearance, torus, frames] = MakeRigOnTorus();
  auto atlas = BuildAtlas(torus, {256, 2});
  ASSERT_TRUE(atlas.ok());
  const AtlasTexels texels = BuildAtlasTexels(torus, *atlas);
  SynthMap map(256, 256, 32, 32, "quilt");  // any map: a scatter of texel centres, three turns
  for (int d = 0; d < texels.count(); ++d)
    map.Set(texels.x[d], texels.y[d], float((d * 7) % 32) + 0.5f, float((d * 13 / 5) % 32) + 0.5f, float(25 * (d % 3) - 25), d);
  FillAtlasGutter(&map, 2);
  // Sample texels 8 atlas texels wide: the continuation from a texel's centre stays inside its texel.
  const double texel_size = 8 / atlas->texels_per_unit;
  auto scene = SurfaceScene::Build(torus);
  ASSERT_TRUE(scene.ok());
  const RenderCamera camera = FramingCamera(torus, 160, 120);
  long checked = 0;
  for (const Eigen::Vector3d& to_light : {Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(1, 0.3, 0.6), Eigen::Vector3d(-0.5, 0.8, 0.4)}) {
    RenderLight light;
    light.vector = to_light.normalized();
    const SurfaceRender r =
        RenderSurface(*scene, AtlasShader(appearance, torus, frames, *atlas, map, texel_size, camera.eye, light), camera, light);
    for (size_t i = 0; i < r.lit.size(); i += 7) {
      if (!r.lit[i]) continue;
      const int f = r.triangle[i];
      const double w[3] = {1.0 - r.u[i] - r.v[i], r.u[i], r.v[i]};
      Eigen::Vector2d a = Eigen::Vector2d::Zero();
      Eigen::Vector3d p = Eigen::Vector3d::Zero(), n = p, s = p;
      for (int k = 0; k < 3; ++k) {
        const int32_t v = torus.faces[f][k];
        a += w[k] * atlas->corner_uv[f][k], p += w[k] * torus.positions[v], n += w[k] * frames.n[v], s += w[k] * frames.s[v];
      }
      n.normalize();
      s = (s - s.dot(n) * n).normalized();
      const Eigen::Vector3d t = n.cross(s);
      const size_t texel = map.index(int(a.x()), int(a.y()));
      const double turn = map.rotation_deg[texel] * M_PI / 180;
      const Eigen::Vector3d x_axis = std::cos(turn) * s + std::sin(turn) * t, y_axis = -std::sin(turn) * s + std::cos(turn) * t;
      auto local = [&](const Eigen::Vector3d& d) { return Eigen::Vector3d(d.dot(x_axis), d.dot(y_axis), d.dot(n)); };
      const Eigen::Vector3f ref = ReferenceLookup(btf, slices, int(map.source_x[texel]), int(map.source_y[texel]),
                                                  local(light.vector), local((camera.eye - p).normalized()));
      const int x = int(i % 160), y = int(i / 160);
      for (int c = 0; c < 3; ++c) ASSERT_NEAR(r.colour.at(x, y, c), ref[c], 1.0 / 255) << "pixel " << x << ", " << y;
      ++checked;
    }
  }
  EXPECT_GT(checked, 300);
}

}  // namespace
}  // namespace mesocap
