#include "mesh/mesh_test_support.h"

#include "mesh/mesh_shapes.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <filesystem>
#include <map>

#include "capture/material_catalog.h"
#include "capture/true_btf_folder.h"
#include "core/directions.h"
#include "core/image_io.h"
#include "tests/testing.h"
#include "synth/exemplar.h"

namespace mesocap::testing {

TriangleMesh IcoSphere(int subdivisions, double radius) { return mesocap::IcoSphere(subdivisions, radius); }
TriangleMesh Torus(int major, int minor, double major_radius, double minor_radius) {
  return mesocap::Torus(major, minor, major_radius, minor_radius);
}

TriangleMesh DoubleTorus(int cells) {
  const double R = 1.0, r = 0.4;
  auto torus = [&](const Eigen::Vector3d& p, double cx) {
    const double q = std::hypot(p.x() - cx, p.y()) - R;
    return std::hypot(q, p.z()) - r;
  };
  auto f = [&](const Eigen::Vector3d& p) { return std::min(torus(p, -0.85), torus(p, 0.85)); };
  const Eigen::Vector3d lo(-2.4, -1.5, -0.6), hi(2.4, 1.5, 0.6);
  const double step = (hi.x() - lo.x()) / cells;
  const Eigen::Vector3i n((hi - lo).x() / step + 1, (hi - lo).y() / step + 1, (hi - lo).z() / step + 1);
  auto corner = [&](int i, int j, int k) { return Eigen::Vector3d(lo + step * Eigen::Vector3d(i, j, k)); };
  auto key = [&](int i, int j, int k) { return (int64_t(k) * (n.y() + 1) + j) * (n.x() + 1) + i; };
  TriangleMesh m;
  std::map<std::pair<int64_t, int64_t>, int32_t> edge_vertex;
  auto vertex_on = [&](int64_t ka, const Eigen::Vector3d& a, double fa, int64_t kb, const Eigen::Vector3d& b, double fb) {
    const auto k = std::minmax(ka, kb);
    auto it = edge_vertex.find(k);
    if (it != edge_vertex.end()) return it->second;
    const double t = fa / (fa - fb);
    m.positions.push_back(a + t * (b - a));
    return edge_vertex[k] = int32_t(m.positions.size() - 1);
  };
  // Six tetrahedra per cube around its main diagonal (corners 0 and 7).
  static const int kTets[6][4] = {{0, 1, 3, 7}, {0, 3, 2, 7}, {0, 2, 6, 7}, {0, 6, 4, 7}, {0, 4, 5, 7}, {0, 5, 1, 7}};
  for (int k = 0; k < n.z(); ++k)
    for (int j = 0; j < n.y(); ++j)
      for (int i = 0; i < n.x(); ++i) {
        Eigen::Vector3d p[8];
        double v[8];
        int64_t id[8];
        for (int c = 0; c < 8; ++c) {
          const int di = c & 1, dj = (c >> 1) & 1, dk = (c >> 2) & 1;
          p[c] = corner(i + di, j + dj, k + dk), id[c] = key(i + di, j + dj, k + dk);
          v[c] = f(p[c]);
          if (v[c] == 0) v[c] = 1e-12;
        }
        for (const auto& tet : kTets) {
          std::vector<int> in, out;
          for (int c : tet) (v[c] < 0 ? in : out).push_back(c);
          if (in.empty() || out.empty()) continue;
          auto cut = [&](int a, int b) { return vertex_on(id[a], p[a], v[a], id[b], p[b], v[b]); };
          std::vector<int32_t> poly;
          if (in.size() == 1) poly = {cut(in[0], out[0]), cut(in[0], out[1]), cut(in[0], out[2])};
          else if (in.size() == 3) poly = {cut(out[0], in[0]), cut(out[0], in[1]), cut(out[0], in[2])};
          else poly = {cut(in[0], out[0]), cut(in[0], out[1]), cut(in[1], out[1]), cut(in[1], out[0])};
          // Orient each polygon with the gradient (outward: f increases).
          const Eigen::Vector3d centre = m.positions[poly[0]];
          const double h = 1e-4;
          const Eigen::Vector3d grad((f(centre + Eigen::Vector3d(h, 0, 0)) - f(centre - Eigen::Vector3d(h, 0, 0))),
                                     (f(centre + Eigen::Vector3d(0, h, 0)) - f(centre - Eigen::Vector3d(0, h, 0))),
                                     (f(centre + Eigen::Vector3d(0, 0, h)) - f(centre - Eigen::Vector3d(0, 0, h))));
          const Eigen::Vector3d normal = (m.positions[poly[1]] - m.positions[poly[0]]).cross(m.positions[poly[2]] - m.positions[poly[0]]);
          if (normal.dot(grad) < 0) std::reverse(poly.begin(), poly.end());
          m.faces.push_back({poly[0], poly[1], poly[2]});
          if (poly.size() == 4) m.faces.push_back({poly[0], poly[2], poly[3]});
        }
      }
  MeshRepairReport report;
  RepairMesh(m, &report);
  return m;
}

TriangleMesh CubeSphere(int n, bool stacked) {
  TriangleMesh m;
  for (int face = 0; face < 6; ++face) {
    const int axis = face / 2;
    const double sign = face % 2 ? -1 : 1;
    const int base = m.vertex_count();
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) {
        Eigen::Vector3d p;
        const double a = 2.0 * i / n - 1, b = 2.0 * j / n - 1;
        p[axis] = sign, p[(axis + 1) % 3] = sign * a, p[(axis + 2) % 3] = b;
        m.positions.push_back(p.normalized());
      }
    // The chart's cell of the UV square (3 x 2 cells, a margin inside each).
    const double cell_u = stacked ? 0 : (face % 3) / 3.0, cell_v = stacked ? 0 : (face / 3) / 2.0;
    const double width = stacked ? 1 : 1 / 3.0, height = stacked ? 1 : 0.5, margin = 0.02;
    auto uv = [&](int i, int j) {
      return Eigen::Vector2d(cell_u + margin * width + (1 - 2 * margin) * width * i / n,
                             cell_v + margin * height + (1 - 2 * margin) * height * j / n);
    };
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const int32_t v00 = base + j * (n + 1) + i, v10 = v00 + 1, v01 = v00 + n + 1, v11 = v01 + 1;
        m.faces.push_back({v00, v10, v11}), m.corner_uv.push_back({uv(i, j), uv(i + 1, j), uv(i + 1, j + 1)});
        m.faces.push_back({v00, v11, v01}), m.corner_uv.push_back({uv(i, j), uv(i + 1, j + 1), uv(i, j + 1)});
      }
  }
  MeshRepairReport report;
  RepairMesh(m, &report);  // welds the cube's edges; the UVs stay per corner
  return m;
}

Exemplar RigGridBtf(const std::string& material_name, int size) {
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> pairs;
  std::vector<Eigen::Vector3d> views{DirectionFromAnglesDeg(0, 0)}, lights{DirectionFromAnglesDeg(0, 0)};
  for (int k = 0; k < 4; ++k) views.push_back(DirectionFromAnglesDeg(30, 90 * k)), views.push_back(DirectionFromAnglesDeg(60, 90 * k + 45));
  for (int k = 0; k < 6; ++k) lights.push_back(DirectionFromAnglesDeg(30, 60 * k)), lights.push_back(DirectionFromAnglesDeg(65, 60 * k + 30));
  for (const auto& v : views)
    for (const auto& l : lights) pairs.push_back({l, v});
  const auto dir = MakeTempDir() / ("btf_" + material_name + "_" + std::to_string(size));
  auto material = Material::Create(material_name);
  MESOCAP_CHECK(material.ok(), material.status().message());
  TrueBtfFolderOptions options;
  options.size = size;
  MESOCAP_CHECK(WriteTrueBtfFolder(*material, pairs, options, dir).ok(), "cannot write the BTF");
  ExemplarOptions o;
  o.features = false;
  auto e = LoadExemplar(dir, o);
  MESOCAP_CHECK(e.ok(), e.status().message());
  return std::move(*e);
}

TextonAnalysis AnalyseImage(const Image& sample) {
  const Exemplar e = ImageExemplar(sample);
  auto analysis = AnalyzeTextons(AppearanceImageCount(e), [&](int k) { return AppearanceLuminance(e, k); }, {});
  MESOCAP_CHECK(analysis.ok(), analysis.status().message());
  return std::move(*analysis);
}

double TensorOrientation(double jss, double jtt, double jst) { return 0.5 * std::atan2(2 * jst, jss - jtt) * 180 / M_PI; }

double AngleBetweenOrientations(double a, double b) {
  const double d = std::fmod(std::abs(a - b), 180.0);
  return std::min(d, 180 - d);
}

double SampleLuminance(const Image& sample, int x, int y) {
  const float* p = sample.pixel(std::clamp(x, 0, sample.width() - 1), std::clamp(y, 0, sample.height() - 1));
  return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
}

double SampleOrientation(const Image& sample) {
  double sxx = 0, syy = 0, sxy = 0;
  for (int y = 0; y < sample.height(); ++y)
    for (int x = 0; x < sample.width(); ++x) {
      const double gx = 0.5 * (SampleLuminance(sample, x + 1, y) - SampleLuminance(sample, x - 1, y));
      const double gt = -0.5 * (SampleLuminance(sample, x, y + 1) - SampleLuminance(sample, x, y - 1));
      sxx += gx * gx, syy += gt * gt, sxy += gx * gt;
    }
  return TensorOrientation(sxx, syy, sxy);
}

DirectionField TorusField(bool along_tube) {
  DirectionField field;
  for (int i = 0; i < 36; ++i) {
    const double u = 2 * M_PI * i / 36;
    for (int j = 0; j < 4; ++j) {
      const double v = 2 * M_PI * j / 4;
      const Eigen::Vector3d n(std::cos(v) * std::cos(u), std::cos(v) * std::sin(u), std::sin(v));
      field.points.push_back(Eigen::Vector3d(std::cos(u), std::sin(u), 0) + 0.35 * n);
      field.directions.push_back(along_tube ? Eigen::Vector3d(-std::sin(u), std::cos(u), 0)
                                            : Eigen::Vector3d(-std::sin(v) * std::cos(u), -std::sin(v) * std::sin(u), std::cos(v)));
    }
  }
  return field;
}

Image HeadOnSample(const SurfaceAppearance& appearance) {
  Image head_on(appearance.width(), appearance.height(), 3);
  for (int y = 0; y < head_on.height(); ++y)
    for (int x = 0; x < head_on.width(); ++x) {
      const Eigen::Vector3f c = appearance.Lookup(x, y, Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitZ());
      for (int k = 0; k < 3; ++k) head_on.at(x, y, k) = c[k];
    }
  return head_on;
}

void ForSixViewsThreeLights(const TriangleMesh& mesh, int size,
                            const std::function<SurfaceRender(const RenderCamera&, const RenderLight&)>& render,
                            const std::function<void(const SurfaceRender&, const RenderCamera&, bool head_on)>& judge) {
  for (const Eigen::Vector3d& view : {Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 0),
                                      Eigen::Vector3d(0, 0, -1), Eigen::Vector3d(-1, 0.2, 0), Eigen::Vector3d(0.3, -1, 0)}) {
    const RenderCamera camera = FramingCamera(mesh, size, size, view);
    const CameraFrame f = camera.Frame();
    const Eigen::Vector3d back = -f.forward;
    bool head_on = true;
    for (const Eigen::Vector3d& l : {back, Eigen::Vector3d(-0.5 * f.right + 0.6 * f.up + 0.6 * back),
                                     Eigen::Vector3d(0.8 * f.right + 0.2 * f.up + 0.5 * back)}) {
      RenderLight light;
      light.vector = l.normalized();
      judge(render(camera, light), camera, head_on);
      head_on = false;
    }
  }
}

Image CentralWindow(const Image& colour, int size) {
  Image window(size, size, 3);
  const int ox = (colour.width() - size) / 2, oy = (colour.height() - size) / 2;
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x)
      for (int c = 0; c < 3; ++c) window.at(x, y, c) = colour.at(x + ox, y + oy, c);
  return window;
}

int TorusEighth(const Eigen::Vector3d& p) { return int(std::floor((std::atan2(p.y(), p.x()) + M_PI) / (2 * M_PI) * 8)) % 8; }

double WorstEighth(const std::vector<Eigen::Vector3d>& tensors, double sample_orientation, const std::string& label) {
  double worst = 0;
  for (size_t k = 0; k < tensors.size(); ++k) {
    const double found = TensorOrientation(tensors[k].x(), tensors[k].y(), tensors[k].z());
    std::printf("field %s, sector %zu: %.1f deg, the sample's %.1f\n", label.c_str(), k, found, sample_orientation);
    worst = std::max(worst, AngleBetweenOrientations(found, sample_orientation));
  }
  return worst;
}

void AddSeamSteps(const SurfaceRender& r, const TriangleMesh& mesh, const RenderCamera& camera,
                  const std::function<bool(size_t, size_t)>& across, SeamSteps* s) {
  const int W = r.width(), H = r.colour.height();
  auto usable = [&](int x, int y) {
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int xx = x + dx, yy = y + dy;
        if (xx < 0 || yy < 0 || xx >= W || yy >= H || !r.lit[size_t(yy) * W + xx]) return false;
      }
    return std::abs(mesh.FaceNormal(r.triangle[size_t(y) * W + x]).dot(camera.RayDirection(x, y))) > 0.3;
  };
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x)
      for (const auto& [dx, dy] : {std::pair{1, 0}, std::pair{0, 1}}) {
        if (x + dx >= W || y + dy >= H || !usable(x, y) || !usable(x + dx, y + dy)) continue;
        double step = 0;
        for (int c = 0; c < 3; ++c) step += std::abs(r.colour.at(x, y, c) - r.colour.at(x + dx, y + dy, c));
        const bool cut = across(size_t(y) * W + x, size_t(y + dy) * W + x + dx);
        (cut ? s->across : s->inside) += step;
        ++(cut ? s->across_pairs : s->inside_pairs);
      }
}

}  // namespace mesocap::testing
