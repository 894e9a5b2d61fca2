#include "mesh/triangle_mesh.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <unordered_map>

#include "core/atomic_file.h"
#include "mesh/mesh_backend.h"

namespace mesocap {
namespace {

struct PositionKey {
  double x, y, z;
  bool operator==(const PositionKey& o) const { return x == o.x && y == o.y && z == o.z; }
};
struct PositionHash {
  size_t operator()(const PositionKey& k) const {
    uint64_t h = 1469598103934665603ull;
    for (double d : {k.x, k.y, k.z}) {
      uint64_t bits;
      std::memcpy(&bits, &d, 8);
      h = (h ^ bits) * 1099511628211ull;
    }
    return size_t(h);
  }
};

// Merges vertices at one position (a file's UV or normal seams split them; synthesis needs the
// surface connected). The first vertex at a position stays, with its normal.
void Weld(TriangleMesh& mesh, MeshRepairReport* report) {
  std::unordered_map<PositionKey, int32_t, PositionHash> first;
  std::vector<int32_t> remap(mesh.positions.size());
  std::vector<Eigen::Vector3d> positions, normals;
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    const Eigen::Vector3d& p = mesh.positions[i];
    auto [it, inserted] = first.emplace(PositionKey{p.x(), p.y(), p.z()}, int32_t(positions.size()));
    if (inserted) {
      positions.push_back(p);
      if (!mesh.normals.empty()) normals.push_back(mesh.normals[i]);
    }
    remap[i] = it->second;
  }
  report->welded_vertices += int(mesh.positions.size() - positions.size());
  for (auto& f : mesh.faces)
    for (int32_t& v : f) v = remap[v];
  mesh.positions = std::move(positions), mesh.normals = std::move(normals);
}

void DropBadFaces(TriangleMesh& mesh, MeshRepairReport* report) {
  std::vector<std::array<int32_t, 3>> kept;
  std::vector<std::array<Eigen::Vector2d, 3>> kept_uv;
  const bool uvs = mesh.corner_uv.size() == mesh.faces.size();
  std::unordered_map<PositionKey, int, PositionHash> seen;  // sorted vertex triple as a key
  const double diagonal = BoundingDiagonal(mesh);
  const double min_area = 1e-14 * diagonal * diagonal;
  for (int f = 0; f < mesh.face_count(); ++f) {
    const auto& t = mesh.faces[f];
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2] || !(mesh.FaceArea(f) > min_area)) {
      ++report->degenerate_faces;
      continue;
    }
    std::array<int32_t, 3> s = t;
    std::sort(s.begin(), s.end());
    if (!seen.emplace(PositionKey{double(s[0]), double(s[1]), double(s[2])}, f).second) {
      ++report->duplicate_faces;
      continue;
    }
    kept.push_back(t);
    if (uvs) kept_uv.push_back(mesh.corner_uv[f]);
  }
  mesh.faces = std::move(kept);
  mesh.corner_uv = std::move(kept_uv);
}

void DropUnreferenced(TriangleMesh& mesh, MeshRepairReport* report) {
  std::vector<int32_t> remap(mesh.positions.size(), -1);
  std::vector<Eigen::Vector3d> positions, normals;
  for (auto& f : mesh.faces)
    for (int32_t& v : f) {
      if (remap[v] < 0) {
        remap[v] = int32_t(positions.size());
        positions.push_back(mesh.positions[v]);
        if (!mesh.normals.empty()) normals.push_back(mesh.normals[v]);
      }
      v = remap[v];
    }
  report->unreferenced_vertices += int(mesh.positions.size() - positions.size());
  mesh.positions = std::move(positions), mesh.normals = std::move(normals);
}

int NonManifoldEdges(const TriangleMesh& mesh) {
  std::map<std::pair<int32_t, int32_t>, int> uses;
  for (const auto& f : mesh.faces)
    for (int k = 0; k < 3; ++k) ++uses[std::minmax(f[k], f[(k + 1) % 3])];
  int n = 0;
  for (const auto& [edge, count] : uses) n += count > 2;
  return n;
}

bool NormalsUsable(const TriangleMesh& mesh) {
  if (mesh.normals.size() != mesh.positions.size()) return false;
  for (const auto& n : mesh.normals)
    if (!(std::abs(n.norm() - 1) < 1e-3)) return false;
  return true;
}

void ComputeNormals(TriangleMesh& mesh) {
  mesh.normals.assign(mesh.positions.size(), Eigen::Vector3d::Zero());
  for (const auto& f : mesh.faces) {  // the cross product's length is twice the area: area weights
    const Eigen::Vector3d n = (mesh.positions[f[1]] - mesh.positions[f[0]]).cross(mesh.positions[f[2]] - mesh.positions[f[0]]);
    for (int32_t v : f) mesh.normals[v] += n;
  }
  for (auto& n : mesh.normals) n = n.norm() > 0 ? Eigen::Vector3d(n.normalized()) : Eigen::Vector3d::UnitZ();
}

}  // namespace

Eigen::Vector3d TriangleMesh::FaceNormal(int f) const {
  const auto& t = faces[f];
  const Eigen::Vector3d n = (positions[t[1]] - positions[t[0]]).cross(positions[t[2]] - positions[t[0]]);
  const double length = n.norm();
  return length > 0 ? Eigen::Vector3d(n / length) : Eigen::Vector3d::Zero();
}

double TriangleMesh::FaceArea(int f) const {
  const auto& t = faces[f];
  return 0.5 * (positions[t[1]] - positions[t[0]]).cross(positions[t[2]] - positions[t[0]]).norm();
}

std::vector<std::string> MeshRepairReport::Lines() const {
  std::vector<std::string> lines;
  auto add = [&](int n, const std::string& what) {
    if (n > 0) lines.push_back(std::to_string(n) + " " + what);
  };
  add(welded_vertices, "vertices at the position of another were merged");
  add(degenerate_faces, "degenerate faces (no area) were dropped");
  add(duplicate_faces, "duplicate faces were dropped");
  add(unreferenced_vertices, "vertices no face uses were dropped");
  add(non_manifold_edges, "edges are shared by more than two faces (kept)");
  add(dropped_primitives, "points or lines in the file were ignored");
  if (normals_recomputed) lines.push_back("normals were computed from the faces");
  return lines;
}

Status RepairMesh(TriangleMesh& mesh, MeshRepairReport* report) {
  MeshRepairReport local;
  if (!report) report = &local;
  for (const auto& p : mesh.positions)
    if (!p.allFinite()) return Status::Error("a vertex position is not a finite number");
  for (const auto& f : mesh.faces)
    for (int32_t v : f)
      if (v < 0 || v >= mesh.vertex_count()) return Status::Error("a face names a vertex the mesh does not have");
  Weld(mesh, report);
  DropBadFaces(mesh, report);
  if (mesh.faces.empty()) return Status::Error("the mesh has no area (every face is degenerate or there are none)");
  DropUnreferenced(mesh, report);
  report->non_manifold_edges = NonManifoldEdges(mesh);
  if (!NormalsUsable(mesh)) {
    ComputeNormals(mesh);
    report->normals_recomputed = true;
  }
  return Status::Ok();
}

StatusOr<TriangleMesh> LoadMesh(const std::filesystem::path& path, MeshRepairReport* report) {
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error)) return Status::Error(path.string() + ": no such mesh file");
  auto backend = LoadMeshBackend();
  if (!backend.ok()) return backend.status();
  auto data = (*backend)->Load(path);
  if (!data.ok()) return data.status();
  TriangleMesh mesh;
  const size_t n = data->positions.size() / 3;
  mesh.positions.resize(n);
  for (size_t i = 0; i < n; ++i)
    mesh.positions[i] = Eigen::Vector3d(data->positions[3 * i], data->positions[3 * i + 1], data->positions[3 * i + 2]);
  if (data->normals.size() == data->positions.size()) {
    mesh.normals.resize(n);
    for (size_t i = 0; i < n; ++i)
      mesh.normals[i] = Eigen::Vector3d(data->normals[3 * i], data->normals[3 * i + 1], data->normals[3 * i + 2]);
  }
  const bool uvs = data->uvs.size() == 2 * n;
  for (size_t f = 0; f + 2 < data->triangles.size(); f += 3) {
    mesh.faces.push_back({int32_t(data->triangles[f]), int32_t(data->triangles[f + 1]), int32_t(data->triangles[f + 2])});
    if (!uvs) continue;
    std::array<Eigen::Vector2d, 3> uv;
    for (int k = 0; k < 3; ++k) uv[k] = Eigen::Vector2d(data->uvs[2 * data->triangles[f + k]], data->uvs[2 * data->triangles[f + k] + 1]);
    mesh.corner_uv.push_back(uv);
  }
  MeshRepairReport local;
  if (!report) report = &local;
  *report = MeshRepairReport();
  report->dropped_primitives = data->dropped_primitives;
  Status repaired = RepairMesh(mesh, report);
  if (!repaired.ok()) return Status::Error(path.string() + ": " + repaired.message());
  return mesh;
}

Status WriteObj(const std::filesystem::path& path, const TriangleMesh& mesh) {
  std::string text;
  text.reserve(mesh.positions.size() * 80);
  char line[160];
  for (const auto& p : mesh.positions) {
    std::snprintf(line, sizeof line, "v %.9g %.9g %.9g\n", p.x(), p.y(), p.z());
    text += line;
  }
  for (const auto& n : mesh.normals) {
    std::snprintf(line, sizeof line, "vn %.7g %.7g %.7g\n", n.x(), n.y(), n.z());
    text += line;
  }
  const bool normals = mesh.normals.size() == mesh.positions.size(), uvs = mesh.corner_uv.size() == mesh.faces.size();
  if (uvs)
    for (const auto& corners : mesh.corner_uv)
      for (const auto& uv : corners) {
        std::snprintf(line, sizeof line, "vt %.9g %.9g\n", uv.x(), uv.y());
        text += line;
      }
  for (int i = 0; i < mesh.face_count(); ++i) {
    text += "f";
    for (int k = 0; k < 3; ++k) {
      const int v = mesh.faces[i][k] + 1;
      const std::string uv = uvs ? std::to_string(3 * i + k + 1) : "";
      text += " " + std::to_string(v) + (normals ? "/" + uv + "/" + std::to_string(v) : uvs ? "/" + uv : "");
    }
    text += "\n";
  }
  return WriteTextAtomically(path, text);
}

double MeanEdgeLength(const TriangleMesh& mesh) {
  double sum = 0;
  long count = 0;
  for (const auto& f : mesh.faces)
    for (int k = 0; k < 3; ++k) sum += (mesh.positions[f[k]] - mesh.positions[f[(k + 1) % 3]]).norm(), ++count;
  return count ? sum / double(count) : 0;
}

double BoundingDiagonal(const TriangleMesh& mesh) {
  if (mesh.positions.empty()) return 0;
  Eigen::Vector3d lo = mesh.positions[0], hi = lo;
  for (const auto& p : mesh.positions) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  return (hi - lo).norm();
}

namespace {
VertexAdjacency FromPairs(int n, std::vector<std::pair<int32_t, int32_t>>& pairs) {
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  VertexAdjacency a;
  a.offsets.assign(n + 1, 0);
  for (const auto& [v, u] : pairs) ++a.offsets[v + 1];
  for (int v = 0; v < n; ++v) a.offsets[v + 1] += a.offsets[v];
  a.list.reserve(pairs.size());
  for (const auto& [v, u] : pairs) a.list.push_back(u);
  return a;
}
}  // namespace

VertexAdjacency VertexNeighbours(const TriangleMesh& mesh) {
  std::vector<std::pair<int32_t, int32_t>> pairs;
  pairs.reserve(mesh.faces.size() * 6);
  for (const auto& f : mesh.faces)
    for (int k = 0; k < 3; ++k) pairs.emplace_back(f[k], f[(k + 1) % 3]), pairs.emplace_back(f[(k + 1) % 3], f[k]);
  return FromPairs(mesh.vertex_count(), pairs);
}

VertexAdjacency VertexFaces(const TriangleMesh& mesh) {
  std::vector<std::pair<int32_t, int32_t>> pairs;
  pairs.reserve(mesh.faces.size() * 3);
  for (int f = 0; f < mesh.face_count(); ++f)
    for (int32_t v : mesh.faces[f]) pairs.emplace_back(v, f);
  return FromPairs(mesh.vertex_count(), pairs);
}

std::vector<std::array<int32_t, 3>> FaceNeighbours(const TriangleMesh& m) {
  std::map<std::pair<int32_t, int32_t>, std::vector<std::pair<int32_t, int>>> edges;
  for (int f = 0; f < m.face_count(); ++f)
    for (int k = 0; k < 3; ++k) edges[std::minmax(m.faces[f][k], m.faces[f][(k + 1) % 3])].push_back({f, k});
  std::vector<std::array<int32_t, 3>> n(m.face_count(), {-1, -1, -1});
  for (const auto& [e, faces] : edges)
    if (faces.size() == 2) n[faces[0].first][faces[0].second] = faces[1].first, n[faces[1].first][faces[1].second] = faces[0].first;
  return n;
}

}  // namespace mesocap
