// Rendering a dressed mesh (Tong 2002 §6, with cast shadows): each vertex shaded from the
// exemplar at its map coordinate, with the light and view directions in its tangent frame
// (mesh/surface_shading.h); each pixel's primary ray cast with Embree, its colour the vertex
// colours blended across the hit triangle (Tong sends vertex colours to the graphics pipeline),
// black where a shadow ray toward the light is blocked (cast shadows between parts of the mesh)
// or the surface faces away from the light. A per-vertex map needs a mesh with at least one
// vertex per rendered pixel for the texture to show at that size.
#pragma once

#include <functional>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "core/image.h"
#include "core/status.h"
#include "mesh/atlas.h"
#include "mesh/mesh_backend.h"
#include "mesh/surface_shading.h"
#include "mesh/surface_textons.h"
#include "mesh/tangent_frames.h"
#include "mesh/triangle_mesh.h"
#include "synth/synth_map.h"

namespace mesocap {

// A camera's unit frame: looking along `forward`, `right` and `up` across the image.
struct CameraFrame {
  Eigen::Vector3d forward, right, up;
};

struct RenderCamera {
  Eigen::Vector3d eye = Eigen::Vector3d(0, 0, 3), target = Eigen::Vector3d::Zero(), up = Eigen::Vector3d::UnitY();
  double fov_y_deg = 35;
  int width = 512, height = 512;
  CameraFrame Frame() const;
  // The primary ray through pixel (x, y)'s centre (unit direction); `frame` is Frame(), made once
  // by a caller that casts many rays.
  Eigen::Vector3d RayDirection(double x, double y, const CameraFrame& frame) const;
  Eigen::Vector3d RayDirection(double x, double y) const { return RayDirection(x, y, Frame()); }
};

// A camera looking at the mesh's box centre from `direction` (mesh frame, toward the camera),
// far enough that the bounding sphere fills the frame.
RenderCamera FramingCamera(const TriangleMesh& mesh, int width, int height,
                           const Eigen::Vector3d& direction = Eigen::Vector3d(0.35, 0.45, 1.0));

struct RenderLight {
  bool point = false;  // false: `vector` is the direction toward a distant light
  Eigen::Vector3d vector = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d DirectionFrom(const Eigen::Vector3d& p) const {  // unit, toward the light
    return point ? Eigen::Vector3d((vector - p).normalized()) : Eigen::Vector3d(vector.normalized());
  }
};

// The mesh as the renderer sees it: its ray-casting scene, built once for any number of lights.
class SurfaceScene {
 public:
  static StatusOr<SurfaceScene> Build(const TriangleMesh& mesh);
  const RayScene& rays() const { return *rays_; }
  const TriangleMesh& mesh() const { return *mesh_; }
  double epsilon() const { return epsilon_; }  // shadow rays start this far off the surface

 private:
  std::shared_ptr<RayScene> rays_;
  const TriangleMesh* mesh_ = nullptr;
  double epsilon_ = 1e-6;
};

// Per vertex, the exemplar's value at the vertex's map texel for the light and the view from
// `eye`, in the vertex's frame.
std::vector<Eigen::Vector3f> ShadeVertices(const SurfaceAppearance& appearance, const TriangleMesh& mesh,
                                           const TangentFrames& frames, const SurfaceMap& map, const Eigen::Vector3d& eye,
                                           const RenderLight& light, int num_threads = -1);

struct SurfaceRender {
  Image colour;                    // linear RGB, black background
  std::vector<int32_t> triangle;   // per pixel, -1 for background
  std::vector<float> u, v;         // barycentrics of the triangle's vertices 1 and 2
  std::vector<uint8_t> lit;        // 1 where the light reaches the surface point
  int width() const { return colour.width(); }
};

// What a lit pixel shows, from its hit: the triangle, the barycentric weights of its vertices 1
// and 2, and the surface point.
using PixelShader = std::function<Eigen::Vector3f(int triangle, float u, float v, const Eigen::Vector3d& point)>;

SurfaceRender RenderSurface(const SurfaceScene& scene, const PixelShader& shade, const RenderCamera& camera,
                            const RenderLight& light, int num_threads = -1);
// Tong's per-vertex colours, blended across each triangle.
SurfaceRender RenderSurface(const SurfaceScene& scene, const std::vector<Eigen::Vector3f>& vertex_colours,
                            const RenderCamera& camera, const RenderLight& light, int num_threads = -1);

// Per pixel from a per-atlas-texel map (a quilt, mesh/surface_quilt.h): the pixel's atlas point,
// the map's texel there with its coordinate continued to the point (ContinueAtlasCoordinate), and
// the light and view in the frame at the point turned by the texel's rotation (the patch's axes).
PixelShader AtlasShader(const SurfaceAppearance& appearance, const TriangleMesh& mesh, const TangentFrames& frames,
                        const Atlas& atlas, const SynthMap& atlas_map, double texel_size, const Eigen::Vector3d& eye,
                        const RenderLight& light);
// The sample texel and local light and view AtlasShader uses at a surface point of face f
// (barycentric weights w); false where the atlas point's texel holds no coordinate.
struct AtlasLookup {
  Eigen::Vector2i texel;
  Eigen::Vector3d light, view;
};
bool LookUpAtlas(const TriangleMesh& mesh, const TangentFrames& frames, const Atlas& atlas, const SynthMap& atlas_map,
                 double texel_size, int f, const Eigen::Vector3d& w, const Eigen::Vector3d& light_direction,
                 const Eigen::Vector3d& view_direction, AtlasLookup* out);

// Linear RGB to an 8-bit sRGB PNG-ready image (values clamped to [0, 1]).
Image ToDisplay(const Image& linear, double exposure = 1.0);

}  // namespace mesocap
