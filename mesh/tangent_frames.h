// A tangent frame (s, t, n) per vertex (Tong 2002 §5.1): n the vertex normal, s the "right"
// direction of a direction field on the surface, t = n x s "up". The field is interpolated from
// a few user-given directions (Turk 2001) or, where none are given, made by relaxation (Wei &
// Levoy 2001), so anisotropic materials follow the surface.
#pragma once

#include <filesystem>
#include <vector>

#include <Eigen/Core>

#include "core/status.h"
#include "mesh/triangle_mesh.h"

namespace mesocap {

struct TangentFrames {
  std::vector<Eigen::Vector3d> s, t, n;
  int size() const { return int(n.size()); }
  // A direction (mesh frame) in vertex v's frame: (d.s, d.t, d.n).
  Eigen::Vector3d ToLocal(int v, const Eigen::Vector3d& d) const { return {d.dot(s[v]), d.dot(t[v]), d.dot(n[v])}; }
};

// A frame at a point inside a face.
struct LocalFrame {
  Eigen::Vector3d s, t, n;
};
// The vertex frames of face f blended with barycentric weights `w`, s made tangent to the blended
// normal.
LocalFrame FaceFrame(const TriangleMesh& mesh, const TangentFrames& frames, int f, const Eigen::Vector3d& w);

// User directions at points on or near the surface (docs/formats.md, `--field`):
// {"points": [[x, y, z], ...], "directions": [[dx, dy, dz], ...]}.
struct DirectionField {
  std::vector<Eigen::Vector3d> points, directions;
};
// The error names the file and the problem (unreadable, mismatched lists, zero directions).
StatusOr<DirectionField> ReadDirectionField(const std::filesystem::path& path);
// A field whose points lie away from the mesh (beyond a tenth of its diagonal from its box)
// belongs to another mesh or another scale: refused, naming the file.
Status CheckFieldMatchesMesh(const DirectionField& field, const TriangleMesh& mesh, const std::filesystem::path& path);

// s from the field's directions weighted by inverse squared distance (Shepard), projected onto
// each vertex's tangent plane; where they cancel, the relaxed field's direction.
TangentFrames FieldFrames(const TriangleMesh& mesh, const DirectionField& field);

// A smooth field by relaxation: every vertex starts from the x axis projected onto its tangent
// plane (the y axis where x is nearly normal), then `iterations` times each direction becomes the
// mean of its own and its neighbours', projected and normalised.
TangentFrames RelaxedFrames(const TriangleMesh& mesh, int iterations = 40);

// Frames from a direction per vertex (projected onto the tangent plane; any vector not nearly
// normal to it).
TangentFrames FramesFromDirections(const TriangleMesh& mesh, const std::vector<Eigen::Vector3d>& directions);

}  // namespace mesocap
