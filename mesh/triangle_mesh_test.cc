#include "mesh/triangle_mesh.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "mesh/mesh_pyramid.h"
#include "mesh/surface_textons.h"
#include "mesh/tangent_frames.h"
#include "mesh/mesh_test_support.h"
#include "tests/testing.h"

namespace mesocap {
namespace {

namespace fs = std::filesystem;

fs::path WriteText(const fs::path& path, const std::string& text) {
  std::ofstream(path) << text;
  return path;
}

TEST(TriangleMesh, ObjRoundTripsThroughAssimp) {
  const fs::path dir = testing::MakeTempDir();
  const TriangleMesh sphere = testing::IcoSphere(2);
  ASSERT_TRUE(WriteObj(dir / "sphere.obj", sphere).ok());
  MeshRepairReport report;
  auto loaded = LoadMesh(dir / "sphere.obj", &report);
  ASSERT_TRUE(loaded.ok()) << loaded.status().message();
  EXPECT_EQ(loaded->vertex_count(), sphere.vertex_count());
  EXPECT_EQ(loaded->face_count(), sphere.face_count());
  EXPECT_FALSE(report.normals_recomputed);
  for (int v = 0; v < loaded->vertex_count(); ++v) EXPECT_NEAR(loaded->positions[v].norm(), 1.0, 1e-6);
}

TEST(TriangleMesh, RepairsWhatIsStandardAndSaysSo) {
  const fs::path dir = testing::MakeTempDir();
  // Two triangles sharing an edge, written with split vertices (as a UV seam splits them), a
  // degenerate face, a duplicate face, an unused vertex and no normals.
  const fs::path path = WriteText(dir / "m.obj",
                                  "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 5 5 5\nvt 0 0\nvt 1 1\n"
                                  "f 1/1 2/1 3/1\nf 4/2 6/2 5/2\nf 1/1 1/1 2/1\nf 3/1 1/1 2/1\n");
  // (Assimp itself drops the unused vertex and the face with a repeated vertex.)
  MeshRepairReport report;
  auto m = LoadMesh(path, &report);
  ASSERT_TRUE(m.ok()) << m.status().message();
  EXPECT_EQ(m->vertex_count(), 4);
  EXPECT_EQ(m->face_count(), 2);
  EXPECT_TRUE(report.normals_recomputed);
  EXPECT_GE(report.welded_vertices, 2);
  EXPECT_EQ(report.duplicate_faces, 1);
  EXPECT_FALSE(report.Lines().empty());
  for (const auto& n : m->normals) EXPECT_NEAR(std::abs(n.z()), 1.0, 1e-9);
}

TEST(TriangleMesh, RepairDropsDegenerateFacesAndUnusedVertices) {
  TriangleMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 0, 0}, {9, 9, 9}};
  m.faces = {{0, 1, 2}, {0, 1, 3}, {1, 1, 2}};  // the second is a line (no area), the third repeats a vertex
  MeshRepairReport report;
  ASSERT_TRUE(RepairMesh(m, &report).ok());
  EXPECT_EQ(report.degenerate_faces, 2);
  EXPECT_EQ(report.unreferenced_vertices, 2);
  EXPECT_EQ(m.vertex_count(), 3);
  EXPECT_TRUE(report.normals_recomputed);
}

TEST(TriangleMesh, BadFilesAreOneLineErrorsNamingTheFile) {
  const fs::path dir = testing::MakeTempDir();
  const fs::path flat = WriteText(dir / "flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n");
  auto a = LoadMesh(flat);
  ASSERT_FALSE(a.ok());
  EXPECT_NE(a.status().message().find("flat.obj"), std::string::npos);
  EXPECT_NE(a.status().message().find("no area"), std::string::npos);
  const fs::path foreign = WriteText(dir / "notes.obj", "this is not a mesh\x01\x02\n");
  auto b = LoadMesh(foreign);
  ASSERT_FALSE(b.ok());
  EXPECT_NE(b.status().message().find("notes.obj"), std::string::npos);
  auto c = LoadMesh(dir / "missing.ply");
  ASSERT_FALSE(c.ok());
  EXPECT_NE(c.status().message().find("missing.ply"), std::string::npos);
}

TEST(MeshPyramid, EachLevelHasAboutAQuarterOfTheVertices) {
  const TriangleMesh sphere = testing::IcoSphere(5);  // 10242 vertices
  auto pyramid = BuildMeshPyramid(sphere, 4);
  ASSERT_TRUE(pyramid.ok()) << pyramid.status().message();
  ASSERT_EQ(pyramid->size(), 4u);
  for (size_t l = 1; l < pyramid->size(); ++l) {
    const double ratio = double((*pyramid)[l].vertex_count()) / (*pyramid)[l - 1].vertex_count();
    EXPECT_NEAR(ratio, 0.25, 0.03) << "level " << l;
    for (const auto& p : (*pyramid)[l].positions) EXPECT_NEAR(p.norm(), 1.0, 0.05);  // still the sphere
  }
}

TEST(MeshPyramid, GridFindsTheNearestPointAsBruteForceDoes) {
  const TriangleMesh torus = testing::Torus(60, 20);
  const PointGrid grid(torus.positions);
  const TriangleMesh probe = testing::IcoSphere(3, 1.6);
  for (const auto& q : probe.positions) {
    int best = 0;
    for (int i = 1; i < torus.vertex_count(); ++i)
      if ((torus.positions[i] - q).squaredNorm() < (torus.positions[best] - q).squaredNorm()) best = i;
    EXPECT_DOUBLE_EQ((torus.positions[grid.Nearest(q)] - q).norm(), (torus.positions[best] - q).norm());
  }
}

TEST(TangentFrames, FollowTheUserFieldAndAreOrthonormal) {
  const TriangleMesh torus = testing::Torus(80, 24);
  DirectionField field;
  for (int i = 0; i < 36; ++i) {  // along the tube, all around
    const double u = 2 * M_PI * i / 36;
    field.points.emplace_back(1.35 * std::cos(u), 1.35 * std::sin(u), 0);
    field.directions.emplace_back(-std::sin(u), std::cos(u), 0);
  }
  const TangentFrames f = FieldFrames(torus, field);
  double worst = 0;
  for (int v = 0; v < torus.vertex_count(); ++v) {
    EXPECT_NEAR(f.s[v].norm(), 1, 1e-9);
    EXPECT_NEAR(f.s[v].dot(f.n[v]), 0, 1e-9);
    EXPECT_NEAR(f.t[v].dot(f.s[v]), 0, 1e-9);
    const Eigen::Vector3d& p = torus.positions[v];
    const Eigen::Vector3d along(-p.y(), p.x(), 0);
    worst = std::max(worst, std::acos(std::min(1.0, f.s[v].dot(along.normalized()))) * 180 / M_PI);
  }
  EXPECT_LT(worst, 2.0);  // the field is the tube's direction every 10 deg: interpolation keeps it
}

TEST(TangentFrames, FieldFromAnotherMeshIsRefused) {
  const TriangleMesh sphere = testing::IcoSphere(2);
  DirectionField field;
  field.points.emplace_back(50, 0, 0);
  field.directions.emplace_back(1, 0, 0);
  const Status s = CheckFieldMatchesMesh(field, sphere, "dirs.json");
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find("dirs.json"), std::string::npos);
}

}  // namespace
}  // namespace mesocap

namespace mesocap {
namespace {

// A non-manifold mesh (a fin: a third face on one of a sphere's edges) is reported, and the mesh
// pyramid and surface synthesis still run (CGAL's soup repair duplicates what is not manifold).
TEST(TriangleMesh, NonManifoldMeshesAreReportedAndStillDressed) {
  TriangleMesh m = testing::IcoSphere(4);
  const auto f0 = m.faces[0];
  m.positions.push_back(1.3 * (m.positions[f0[0]] + m.positions[f0[1]]) / 2);
  m.normals.push_back(m.positions.back().normalized());
  m.faces.push_back({f0[0], f0[1], int32_t(m.positions.size() - 1)});
  MeshRepairReport report;
  ASSERT_TRUE(RepairMesh(m, &report).ok());
  EXPECT_EQ(report.non_manifold_edges, 1);
  auto pyramid = BuildMeshPyramid(m, 3);
  ASSERT_TRUE(pyramid.ok()) << pyramid.status().message();
  EXPECT_EQ(pyramid->size(), 3u);
  const TextonAnalysis analysis = testing::AnalyseImage(testing::PhotoCrop("gravel", 32));
  auto map = SurfaceTextonSynthesis(m, RelaxedFrames(m), analysis, {}, nullptr);
  ASSERT_TRUE(map.ok()) << map.status().message();
  EXPECT_EQ(map->size(), m.vertex_count());
}

}  // namespace
}  // namespace mesocap
