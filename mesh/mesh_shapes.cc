#include "mesh/mesh_shapes.h"

#include <cmath>
#include <map>

namespace mesocap {

TriangleMesh IcoSphere(int subdivisions, double radius) {
  const double t = (1 + std::sqrt(5.0)) / 2;
  TriangleMesh m;
  for (const auto& p : std::vector<Eigen::Vector3d>{{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                                                    {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}})
    m.positions.push_back(p.normalized());
  m.faces = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
             {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8}, {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<int, int>, int> middle;
    auto mid = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      auto it = middle.find(key);
      if (it != middle.end()) return it->second;
      m.positions.push_back((m.positions[a] + m.positions[b]).normalized());
      return middle[key] = int(m.positions.size()) - 1;
    };
    std::vector<std::array<int32_t, 3>> faces;
    for (const auto& f : m.faces) {
      const int a = mid(f[0], f[1]), b = mid(f[1], f[2]), c = mid(f[2], f[0]);
      faces.push_back({f[0], a, c}), faces.push_back({f[1], b, a}), faces.push_back({f[2], c, b}), faces.push_back({a, b, c});
    }
    m.faces = std::move(faces);
  }
  for (auto& p : m.positions) m.normals.push_back(p), p *= radius;
  return m;
}

TriangleMesh Torus(int major, int minor, double R, double r) {
  TriangleMesh m;
  for (int i = 0; i < major; ++i)
    for (int j = 0; j < minor; ++j) {
      const double u = 2 * M_PI * i / major, v = 2 * M_PI * j / minor;
      const Eigen::Vector3d n(std::cos(v) * std::cos(u), std::cos(v) * std::sin(u), std::sin(v));
      m.positions.push_back(Eigen::Vector3d(R * std::cos(u), R * std::sin(u), 0) + r * n);
      m.normals.push_back(n);
    }
  auto at = [&](int i, int j) { return int32_t(((i + major) % major) * minor + (j + minor) % minor); };
  for (int i = 0; i < major; ++i)
    for (int j = 0; j < minor; ++j) {
      m.faces.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      m.faces.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  return m;
}

}  // namespace mesocap
