#include "mesh/surface_render.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/parallel.h"
#include "mesh/surface_quilt.h"

namespace mesocap {

CameraFrame RenderCamera::Frame() const {
  CameraFrame f;
  f.forward = (target - eye).normalized();
  f.right = f.forward.cross(up).normalized();
  f.up = f.right.cross(f.forward);
  return f;
}

Eigen::Vector3d RenderCamera::RayDirection(double x, double y, const CameraFrame& f) const {
  const double half = std::tan(fov_y_deg * M_PI / 360.0);
  const double px = (2 * (x + 0.5) / width - 1) * half * width / height;
  const double py = (1 - 2 * (y + 0.5) / height) * half;
  return (f.forward + px * f.right + py * f.up).normalized();
}

RenderCamera FramingCamera(const TriangleMesh& mesh, int width, int height, const Eigen::Vector3d& direction) {
  Eigen::Vector3d lo = mesh.positions[0], hi = lo;
  for (const auto& p : mesh.positions) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  RenderCamera c;
  c.width = width, c.height = height;
  c.target = 0.5 * (lo + hi);
  const double radius = 0.5 * (hi - lo).norm();
  const double half = std::tan(c.fov_y_deg * M_PI / 360.0) * std::min(1.0, double(width) / height);
  c.eye = c.target + direction.normalized() * (radius / std::sin(std::atan(half)) * 1.02);
  c.up = std::abs(direction.normalized().dot(Eigen::Vector3d::UnitY())) > 0.99 ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d::UnitY();
  return c;
}

StatusOr<SurfaceScene> SurfaceScene::Build(const TriangleMesh& mesh) {
  auto backend = LoadMeshBackend();
  if (!backend.ok()) return backend.status();
  std::vector<float> positions;
  std::vector<uint32_t> triangles;
  positions.reserve(3 * mesh.positions.size());
  for (const auto& p : mesh.positions) positions.insert(positions.end(), {float(p.x()), float(p.y()), float(p.z())});
  for (const auto& f : mesh.faces) triangles.insert(triangles.end(), {uint32_t(f[0]), uint32_t(f[1]), uint32_t(f[2])});
  auto rays = (*backend)->BuildScene(positions, triangles);
  if (!rays.ok()) return rays.status();
  SurfaceScene s;
  s.rays_ = std::move(*rays);
  s.mesh_ = &mesh;
  s.epsilon_ = 1e-5 * std::max(1e-12, BoundingDiagonal(mesh));
  return s;
}

std::vector<Eigen::Vector3f> ShadeVertices(const SurfaceAppearance& appearance, const TriangleMesh& mesh,
                                           const TangentFrames& frames, const SurfaceMap& map, const Eigen::Vector3d& eye,
                                           const RenderLight& light, int num_threads) {
  std::vector<Eigen::Vector3f> colours(mesh.vertex_count());
  const int blocks = (mesh.vertex_count() + 1023) / 1024;
  ParallelFor(0, blocks, [&](int b) {
    for (int v = b * 1024; v < std::min(mesh.vertex_count(), (b + 1) * 1024); ++v) {
      const Eigen::Vector3d& p = mesh.positions[v];
      const Eigen::Vector3d l = frames.ToLocal(v, light.DirectionFrom(p)), w = frames.ToLocal(v, (eye - p).normalized());
      const Eigen::Vector2i t = map.SourceTexel(v);
      colours[v] = appearance.Lookup(t.x(), t.y(), l, w);
    }
  }, num_threads);
  return colours;
}

SurfaceRender RenderSurface(const SurfaceScene& scene, const std::vector<Eigen::Vector3f>& vertex_colours,
                            const RenderCamera& camera, const RenderLight& light, int num_threads) {
  const TriangleMesh& mesh = scene.mesh();
  return RenderSurface(scene, [&](int t, float u, float v, const Eigen::Vector3d&) {
    const auto& f = mesh.faces[t];
    return Eigen::Vector3f((1 - u - v) * vertex_colours[f[0]] + u * vertex_colours[f[1]] + v * vertex_colours[f[2]]);
  }, camera, light, num_threads);
}

SurfaceRender RenderSurface(const SurfaceScene& scene, const PixelShader& shade, const RenderCamera& camera,
                            const RenderLight& light, int num_threads) {
  const TriangleMesh& mesh = scene.mesh();
  const int W = camera.width, H = camera.height;
  SurfaceRender r;
  r.colour = Image(W, H, 3);
  r.triangle.assign(size_t(W) * H, -1);
  r.u.assign(size_t(W) * H, 0), r.v.assign(size_t(W) * H, 0), r.lit.assign(size_t(W) * H, 0);
  const float inf = std::numeric_limits<float>::infinity();
  const CameraFrame frame = camera.Frame();
  ParallelFor(0, H, [&](int y) {
    for (int x = 0; x < W; ++x) {
      const Eigen::Vector3d d = camera.RayDirection(x, y, frame);
      const float origin[3] = {float(camera.eye.x()), float(camera.eye.y()), float(camera.eye.z())};
      const float direction[3] = {float(d.x()), float(d.y()), float(d.z())};
      const RayHit hit = scene.rays().Intersect(origin, direction, inf);
      if (hit.triangle < 0) continue;
      const size_t i = size_t(y) * W + x;
      r.triangle[i] = hit.triangle, r.u[i] = hit.u, r.v[i] = hit.v;
      const Eigen::Vector3d p = camera.eye + double(hit.t) * d;
      const Eigen::Vector3d l = light.DirectionFrom(p);
      Eigen::Vector3d n = mesh.FaceNormal(hit.triangle);
      if (n.dot(d) > 0) n = -n;  // the side the camera sees
      // Facing away from the light: dark (the vertex colours fade to black toward the terminator,
      // their lights going below the vertices' horizons).
      if (n.dot(l) <= 0) continue;
      const Eigen::Vector3d o = p + scene.epsilon() * n;
      const float so[3] = {float(o.x()), float(o.y()), float(o.z())}, sd[3] = {float(l.x()), float(l.y()), float(l.z())};
      const float far = light.point ? float((light.vector - o).norm()) : inf;
      if (scene.rays().Occluded(so, sd, 0.f, far)) continue;
      r.lit[i] = 1;
      const Eigen::Vector3f c = shade(hit.triangle, hit.u, hit.v, p);
      for (int k = 0; k < 3; ++k) r.colour.at(x, y, k) = c[k];
    }
  }, num_threads);
  return r;
}

bool LookUpAtlas(const TriangleMesh& mesh, const TangentFrames& frames, const Atlas& atlas, const SynthMap& map,
                 double texel_size, int f, const Eigen::Vector3d& w, const Eigen::Vector3d& light_direction,
                 const Eigen::Vector3d& view_direction, AtlasLookup* out) {
  const auto& uv = atlas.corner_uv[f];
  const Eigen::Vector2d a = w[0] * uv[0] + w[1] * uv[1] + w[2] * uv[2];
  const int ax = std::clamp(int(std::floor(a.x())), 0, map.width - 1), ay = std::clamp(int(std::floor(a.y())), 0, map.height - 1);
  if (!map.filled(ax, ay)) return false;
  // The point's offset from the texel's centre, carried from the atlas onto the face.
  const auto& c = mesh.faces[f];
  Eigen::Matrix<double, 3, 2> E;
  E.col(0) = mesh.positions[c[1]] - mesh.positions[c[0]], E.col(1) = mesh.positions[c[2]] - mesh.positions[c[0]];
  Eigen::Matrix2d D;
  D.col(0) = uv[1] - uv[0], D.col(1) = uv[2] - uv[0];
  const Eigen::Vector3d offset = std::abs(D.determinant()) > 1e-18
                                     ? Eigen::Vector3d(E * D.inverse() * (a - Eigen::Vector2d(ax + 0.5, ay + 0.5)))
                                     : Eigen::Vector3d::Zero();
  const LocalFrame fr = FaceFrame(mesh, frames, f, w);
  const size_t i = map.index(ax, ay);
  const Eigen::Vector2d s = ContinueAtlasCoordinate(map, i, fr.s, fr.t, offset, texel_size);
  out->texel = Eigen::Vector2i(std::clamp(int(std::floor(s.x())), 0, map.sample_width - 1),
                               std::clamp(int(std::floor(s.y())), 0, map.sample_height - 1));
  const double r = map.rotation_deg[i] * M_PI / 180;
  const Eigen::Vector3d x_axis = std::cos(r) * fr.s + std::sin(r) * fr.t, y_axis = -std::sin(r) * fr.s + std::cos(r) * fr.t;
  out->light = Eigen::Vector3d(light_direction.dot(x_axis), light_direction.dot(y_axis), light_direction.dot(fr.n));
  out->view = Eigen::Vector3d(view_direction.dot(x_axis), view_direction.dot(y_axis), view_direction.dot(fr.n));
  return true;
}

PixelShader AtlasShader(const SurfaceAppearance& appearance, const TriangleMesh& mesh, const TangentFrames& frames,
                        const Atlas& atlas, const SynthMap& atlas_map, double texel_size, const Eigen::Vector3d& eye,
                        const RenderLight& light) {
  return [&, eye, light, texel_size](int t, float u, float v, const Eigen::Vector3d& p) {
    AtlasLookup look;
    if (!LookUpAtlas(mesh, frames, atlas, atlas_map, texel_size, t, Eigen::Vector3d(1 - u - v, u, v), light.DirectionFrom(p),
                     (eye - p).normalized(), &look))
      return Eigen::Vector3f::Zero().eval();
    return appearance.Lookup(look.texel.x(), look.texel.y(), look.light, look.view);
  };
}

Image ToDisplay(const Image& linear, double exposure) {
  Image out(linear.width(), linear.height(), 3);
  for (size_t i = 0; i < out.size(); ++i) out.data()[i] = std::clamp(float(linear.data()[i] * exposure), 0.f, 1.f);
  return out;
}

}  // namespace mesocap
