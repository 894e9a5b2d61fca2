// Meshes the mesh tests write: made here in closed form, so each test knows its surface exactly.
#pragma once

#include <functional>
#include <string>

#include "core/image.h"
#include "mesh/surface_render.h"
#include "mesh/tangent_frames.h"
#include "mesh/triangle_mesh.h"
#include "synth/exemplar.h"
#include "synth/synth_test_support.h"  // PhotoCrop, shared with the synthesis tests
#include "synth/texton_analysis.h"

namespace mesocap::testing {

// A unit sphere by `subdivisions` of an icosahedron (10 x 4^s + 2 vertices), no UVs.
TriangleMesh IcoSphere(int subdivisions, double radius = 1.0);
// A torus around the z axis, `major` x `minor` quads, each split in two.
TriangleMesh Torus(int major, int minor, double major_radius = 1.0, double minor_radius = 0.35);
// A genus-2 surface (two overlapping tori's union, the zero set of min(f1, f2)) by marching
// tetrahedra on a grid of `cells` along x: no global parameterisation exists.
TriangleMesh DoubleTorus(int cells);

// A unit sphere from a cube's six faces (n x n quads each, pushed onto the sphere) with its own
// UVs: each cube face a chart in a 3 x 2 layout of the UV square with margins; with `stacked`,
// every face's UVs on the same square instead (overlapping charts).
TriangleMesh CubeSphere(int n, bool stacked = false);

// The virtual rig's `material` as a true BTF of 9 views x 13 lights per view, `size` texels a side,
// written under the test's temp folder and loaded without features.
Exemplar RigGridBtf(const std::string& material, int size);
// The texton analysis of an image exemplar, default options.
TextonAnalysis AnalyseImage(const Image& sample);

// Orientation tests: the dominant orientation (deg, mod 180) of a structure tensor summed from
// gradients (gs, gt); the angle between two orientations; a sample texel's luminance (clamped);
// the sample's own orientation in (x, -y) (s runs along its x, t up its rows); and a user field on
// Torus(): along the tube or around it (36 x 4 points).
double TensorOrientation(double jss, double jtt, double jst);
double AngleBetweenOrientations(double a, double b);
double SampleLuminance(const Image& sample, int x, int y);
double SampleOrientation(const Image& sample);
DirectionField TorusField(bool along_tube);
// The eighth of Torus() (by angle about z) a point lies in; each eighth's orientation from its
// summed tensor (jss, jtt, jst), printed beside the sample's, and the largest difference.
int TorusEighth(const Eigen::Vector3d& p);
double WorstEighth(const std::vector<Eigen::Vector3d>& tensors, double sample_orientation, const std::string& label);

// Rendering tests: the sample as a head-on light and view show it; each of six views of the mesh
// (framed, size x size) under three lights (head-on, from the upper left, grazing from the right),
// rendered by `render` and handed to `judge` with whether the light is head-on; the central
// window of a render.
Image HeadOnSample(const SurfaceAppearance& appearance);
void ForSixViewsThreeLights(const TriangleMesh& mesh, int size,
                            const std::function<SurfaceRender(const RenderCamera&, const RenderLight&)>& render,
                            const std::function<void(const SurfaceRender&, const RenderCamera&, bool head_on)>& judge);
Image CentralWindow(const Image& colour, int size);

// Seams in renders: over neighbouring pixel pairs both lit with their 3 x 3 neighbourhoods and on
// triangles facing the camera (|n.v| > 0.3: away from silhouettes), the mean colour step of the
// pairs `across` says straddle a cut (pixel indices) over that of the others.
struct SeamSteps {
  double across = 0, inside = 0;
  long across_pairs = 0, inside_pairs = 0;
  double ratio() const { return (across / across_pairs) / (inside / inside_pairs); }
};
void AddSeamSteps(const SurfaceRender& r, const TriangleMesh& mesh, const RenderCamera& camera,
                  const std::function<bool(size_t pixel_a, size_t pixel_b)>& across, SeamSteps* steps);

}  // namespace mesocap::testing
