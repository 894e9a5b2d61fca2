#include "mesh/tangent_frames.h"

#include <cmath>

#include "core/atomic_file.h"
#include "core/json.h"

namespace mesocap {
namespace {

// d projected onto the plane normal to n; zero when d is (nearly) along n.
Eigen::Vector3d Projected(const Eigen::Vector3d& d, const Eigen::Vector3d& n) { return d - d.dot(n) * n; }

Eigen::Vector3d AxisStart(const Eigen::Vector3d& n) {
  const Eigen::Vector3d x = Projected(Eigen::Vector3d::UnitX(), n);
  return x.norm() > 0.3 ? x : Projected(Eigen::Vector3d::UnitY(), n);
}

}  // namespace

TangentFrames FramesFromDirections(const TriangleMesh& mesh, const std::vector<Eigen::Vector3d>& directions) {
  TangentFrames f;
  const int n = mesh.vertex_count();
  f.s.resize(n), f.t.resize(n), f.n = mesh.normals;
  for (int v = 0; v < n; ++v) {
    Eigen::Vector3d s = Projected(directions[v], f.n[v]);
    if (s.norm() < 1e-9) s = AxisStart(f.n[v]);
    f.s[v] = s.normalized();
    f.t[v] = f.n[v].cross(f.s[v]);
  }
  return f;
}

TangentFrames RelaxedFrames(const TriangleMesh& mesh, int iterations) {
  const int n = mesh.vertex_count();
  std::vector<Eigen::Vector3d> d(n), next(n);
  for (int v = 0; v < n; ++v) d[v] = AxisStart(mesh.normals[v]).normalized();
  const VertexAdjacency ring = VertexNeighbours(mesh);
  for (int it = 0; it < iterations; ++it) {
    for (int v = 0; v < n; ++v) {
      Eigen::Vector3d sum = d[v];
      for (const int32_t* u = ring.begin(v); u != ring.end(v); ++u) sum += d[*u];
      const Eigen::Vector3d p = Projected(sum, mesh.normals[v]);
      next[v] = p.norm() > 1e-9 ? Eigen::Vector3d(p.normalized()) : d[v];
    }
    d.swap(next);
  }
  return FramesFromDirections(mesh, d);
}

TangentFrames FieldFrames(const TriangleMesh& mesh, const DirectionField& field) {
  const double scale = std::max(1e-12, 1e-3 * BoundingDiagonal(mesh));
  const TangentFrames relaxed = RelaxedFrames(mesh);
  std::vector<Eigen::Vector3d> d(mesh.vertex_count());
  for (int v = 0; v < mesh.vertex_count(); ++v) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (size_t i = 0; i < field.points.size(); ++i)
      sum += field.directions[i] / ((mesh.positions[v] - field.points[i]).squaredNorm() + scale * scale);
    const Eigen::Vector3d p = Projected(sum, mesh.normals[v]);
    d[v] = p.norm() > 1e-6 * sum.norm() && sum.norm() > 0 ? p : relaxed.s[v];
  }
  return FramesFromDirections(mesh, d);
}

StatusOr<DirectionField> ReadDirectionField(const std::filesystem::path& path) {
  auto text = ReadTextFile(path);
  if (!text.ok()) return text.status();
  DirectionField field;
  try {
    const Json j = Json::parse(*text);
    for (const auto& p : j.at("points")) field.points.emplace_back(p.at(0).get<double>(), p.at(1).get<double>(), p.at(2).get<double>());
    for (const auto& p : j.at("directions"))
      field.directions.emplace_back(p.at(0).get<double>(), p.at(1).get<double>(), p.at(2).get<double>());
  } catch (const std::exception& e) {
    return Status::Error(path.string() + ": not a direction field (" + e.what() + "); expected {\"points\": [[x, y, z], ...], "
                         "\"directions\": [[dx, dy, dz], ...]}");
  }
  if (field.points.empty()) return Status::Error(path.string() + ": the direction field has no points");
  if (field.points.size() != field.directions.size())
    return Status::Error(path.string() + ": the direction field has " + std::to_string(field.points.size()) + " points but " +
                         std::to_string(field.directions.size()) + " directions");
  for (size_t i = 0; i < field.points.size(); ++i)
    if (!field.points[i].allFinite() || !field.directions[i].allFinite() || !(field.directions[i].norm() > 0))
      return Status::Error(path.string() + ": direction " + std::to_string(i) + " is zero or not a number");
  return field;
}

Status CheckFieldMatchesMesh(const DirectionField& field, const TriangleMesh& mesh, const std::filesystem::path& path) {
  Eigen::Vector3d lo = mesh.positions[0], hi = lo;
  for (const auto& p : mesh.positions) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const double margin = 0.1 * (hi - lo).norm();
  for (size_t i = 0; i < field.points.size(); ++i) {
    const Eigen::Vector3d& p = field.points[i];
    const Eigen::Vector3d outside = (lo - p).cwiseMax(p - hi).cwiseMax(0.0);
    if (outside.norm() > margin)
      return Status::Error(path.string() + ": point " + std::to_string(i) + " lies " + std::to_string(outside.norm()) +
                           " away from the mesh's box (more than a tenth of its diagonal): the field is not for this mesh");
  }
  return Status::Ok();
}

LocalFrame FaceFrame(const TriangleMesh& m, const TangentFrames& frames, int f, const Eigen::Vector3d& w) {
  const auto& c = m.faces[f];
  Eigen::Vector3d n = w[0] * frames.n[c[0]] + w[1] * frames.n[c[1]] + w[2] * frames.n[c[2]];
  n = n.norm() > 1e-12 ? n.normalized() : m.FaceNormal(f);
  Eigen::Vector3d s = w[0] * frames.s[c[0]] + w[1] * frames.s[c[1]] + w[2] * frames.s[c[2]];
  s -= s.dot(n) * n;
  if (s.norm() < 1e-12) s = frames.s[c[0]] - frames.s[c[0]].dot(n) * n;
  s.normalize();
  return {s, n.cross(s), n};
}

}  // namespace mesocap
