#include "mesh/surface_map_file.h"

#include <cmath>
#include <cstring>
#include <sstream>

#include "core/atomic_file.h"

namespace mesocap {
namespace {

constexpr const char* kMagic = "comment mesocap surface map 1";
constexpr int kVertexFloats = 11;  // x y z, nx ny nz, sx sy sz, source_x source_y (then an int label)
constexpr size_t kVertexBytes = kVertexFloats * 4 + 4, kFaceBytes = 1 + 3 * 4, kTexcoordBytes = 1 + 6 * 4;
constexpr const char* kTexcoordProperty = "property list uchar float texcoord";  // MeshLab's per-corner UVs
constexpr long kMaxElements = 1L << 28;

const char* const kVertexProperties[] = {"x", "y", "z", "nx", "ny", "nz", "sx", "sy", "sz", "source_x", "source_y"};

void Put(std::string& out, const void* p, size_t n) { out.append(static_cast<const char*>(p), n); }

}  // namespace

Status WriteDressedMesh(const std::filesystem::path& path, const DressedMesh& d) {
  const TriangleMesh& m = d.mesh;
  std::ostringstream header;
  header << "ply\nformat binary_little_endian 1.0\n" << kMagic << "\ncomment method " << d.map.method << "\ncomment sample_size "
         << d.map.sample_width << " " << d.map.sample_height << "\n";
  char texel[64];
  std::snprintf(texel, sizeof texel, "%.17g", d.map.texel_size);
  header << "comment texel_size " << texel << "\n";
  const bool atlas = d.has_atlas();
  if (atlas) header << "comment atlas_size " << d.atlas.size << "\n";
  header << "element vertex " << m.vertex_count() << "\n";
  for (const char* name : kVertexProperties) header << "property float " << name << "\n";
  header << "property int label\nelement face " << m.face_count() << "\nproperty list uchar int vertex_indices\n";
  if (atlas) header << kTexcoordProperty << "\n";
  header << "end_header\n";
  std::string out = header.str();
  out.reserve(out.size() + m.positions.size() * kVertexBytes + m.faces.size() * kFaceBytes);
  for (int v = 0; v < m.vertex_count(); ++v) {
    const float values[kVertexFloats] = {float(m.positions[v].x()), float(m.positions[v].y()), float(m.positions[v].z()),
                                         float(d.frames.n[v].x()),  float(d.frames.n[v].y()),  float(d.frames.n[v].z()),
                                         float(d.frames.s[v].x()),  float(d.frames.s[v].y()),  float(d.frames.s[v].z()),
                                         d.map.source_x[v],         d.map.source_y[v]};
    Put(out, values, sizeof values);
    const int32_t label = d.map.label.empty() ? -1 : d.map.label[v];
    Put(out, &label, 4);
  }
  for (int f = 0; f < m.face_count(); ++f) {
    const uint8_t three = 3, six = 6;
    Put(out, &three, 1);
    Put(out, m.faces[f].data(), 12);
    if (!atlas) continue;
    Put(out, &six, 1);
    for (const Eigen::Vector2d& uv : d.atlas.corner_uv[f]) {
      const float t[2] = {float(uv.x() / d.atlas.size), float(uv.y() / d.atlas.size)};
      Put(out, t, sizeof t);
    }
  }
  return WriteTextAtomically(path, out);
}

StatusOr<DressedMesh> ReadDressedMesh(const std::filesystem::path& path) {
  auto bytes = ReadTextFile(path);
  if (!bytes.ok()) return bytes.status();
  const std::string& data = *bytes;
  auto bad = [&](const std::string& why) { return Status::Error(path.string() + ": not a mesocap surface map (" + why + ")"); };
  const size_t end = data.find("end_header\n");
  if (end == std::string::npos || data.compare(0, 4, "ply\n") != 0) return bad("no PLY header");
  std::istringstream header(data.substr(0, end));
  std::string line;
  DressedMesh d;
  long vertices = -1, faces = -1;
  std::vector<std::string> properties;
  bool magic = false, binary = false;
  while (std::getline(header, line)) {
    std::istringstream words(line);
    std::string a, b, c;
    words >> a >> b;
    if (line == kMagic) magic = true;
    else if (line == "format binary_little_endian 1.0") binary = true;
    else if (a == "comment" && b == "method") words >> d.map.method;
    else if (a == "comment" && b == "sample_size") words >> d.map.sample_width >> d.map.sample_height;
    else if (a == "comment" && b == "texel_size") words >> d.map.texel_size;
    else if (a == "comment" && b == "atlas_size") words >> d.atlas.size;
    else if (a == "element" && b == "vertex") words >> vertices;
    else if (a == "element" && b == "face") words >> faces;
    else if (a == "property") properties.push_back(line);
  }
  if (!magic || !binary) return bad("not written by mesocap decorate");
  std::vector<std::string> expected;
  for (const char* name : kVertexProperties) expected.push_back(std::string("property float ") + name);
  expected.push_back("property int label");
  expected.push_back("property list uchar int vertex_indices");
  const bool atlas = !properties.empty() && properties.back() == kTexcoordProperty;
  if (atlas) expected.push_back(kTexcoordProperty);
  if (properties != expected) return bad("unexpected vertex or face properties");
  if (atlas != (d.atlas.size > 0) || d.atlas.size < 0 || d.atlas.size > 16384) return bad("atlas size and texture coordinates do not match");
  if (vertices < 3 || faces < 1 || vertices > kMaxElements || faces > kMaxElements) return bad("vertex or face count out of range");
  if (d.map.sample_width < 1 || d.map.sample_height < 1 || d.map.sample_width > 32768 || d.map.sample_height > 32768)
    return bad("sample size out of range");
  if (!(d.map.texel_size > 0) || !std::isfinite(d.map.texel_size)) return bad("texel size is not a positive length");
  const size_t body = end + std::strlen("end_header\n");
  if (data.size() != body + size_t(vertices) * kVertexBytes + size_t(faces) * (kFaceBytes + (atlas ? kTexcoordBytes : 0)))
    return bad("the file's size does not match its counts");
  const char* p = data.data() + body;
  for (long v = 0; v < vertices; ++v) {
    float f[kVertexFloats];
    int32_t label;
    std::memcpy(f, p, sizeof f), std::memcpy(&label, p + sizeof f, 4);
    p += kVertexBytes;
    for (float x : f)
      if (!std::isfinite(x)) return bad("vertex " + std::to_string(v) + " has a value that is not a number");
    if (!(f[9] >= 0 && f[9] < d.map.sample_width && f[10] >= 0 && f[10] < d.map.sample_height))
      return bad("vertex " + std::to_string(v) + "'s sample coordinate lies outside the sample");
    d.mesh.positions.emplace_back(f[0], f[1], f[2]);
    const Eigen::Vector3d n(f[3], f[4], f[5]), s(f[6], f[7], f[8]);
    if (std::abs(n.norm() - 1) > 1e-3 || std::abs(s.norm() - 1) > 1e-3 || std::abs(n.dot(s)) > 1e-3)
      return bad("vertex " + std::to_string(v) + "'s frame is not orthonormal");
    d.mesh.normals.push_back(n.normalized());
    d.frames.n.push_back(n.normalized());
    d.frames.s.push_back((s - s.dot(d.frames.n.back()) * d.frames.n.back()).normalized());
    d.frames.t.push_back(d.frames.n.back().cross(d.frames.s.back()));
    d.map.source_x.push_back(f[9]), d.map.source_y.push_back(f[10]), d.map.label.push_back(label);
  }
  for (long i = 0; i < faces; ++i) {
    if (uint8_t(*p) != 3) return bad("face " + std::to_string(i) + " is not a triangle");
    std::array<int32_t, 3> f;
    std::memcpy(f.data(), p + 1, 12);
    p += kFaceBytes;
    for (int32_t v : f)
      if (v < 0 || v >= vertices) return bad("face " + std::to_string(i) + " names a vertex the file does not have");
    d.mesh.faces.push_back(f);
    if (!atlas) continue;
    if (uint8_t(*p) != 6) return bad("face " + std::to_string(i) + " does not have three texture coordinates");
    float t[6];
    std::memcpy(t, p + 1, sizeof t);
    p += kTexcoordBytes;
    std::array<Eigen::Vector2d, 3> uv;
    for (int k = 0; k < 3; ++k) {
      if (!(t[2 * k] >= 0 && t[2 * k] <= 1 && t[2 * k + 1] >= 0 && t[2 * k + 1] <= 1))
        return bad("face " + std::to_string(i) + "'s texture coordinates lie outside the atlas");
      uv[k] = Eigen::Vector2d(t[2 * k], t[2 * k + 1]) * d.atlas.size;
    }
    d.atlas.corner_uv.push_back(uv);
  }
  return d;
}

}  // namespace mesocap
