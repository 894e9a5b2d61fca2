// Meshes made in closed form: the demo's sphere and torus, and the tests'.
#pragma once

#include "mesh/triangle_mesh.h"

namespace mesocap {

// A sphere by `subdivisions` of an icosahedron (10 x 4^s + 2 vertices), no UVs.
TriangleMesh IcoSphere(int subdivisions, double radius = 1.0);
// A torus around the z axis, `major` x `minor` quads, each split in two.
TriangleMesh Torus(int major, int minor, double major_radius = 1.0, double minor_radius = 0.35);

}  // namespace mesocap
