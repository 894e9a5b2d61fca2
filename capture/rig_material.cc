#include "capture/rig_material.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>

#include "core/parallel.h"

namespace mesocap {
namespace {

constexpr double kPi = std::numbers::pi;

// Deterministic hash of lattice coordinates -> [0,1).
double Hash01(int64_t x, int64_t y, uint64_t salt) {
  uint64_t h = uint64_t(x) * 0x9E3779B97F4A7C15ull ^ (uint64_t(y) + 0x632BE59BD9B4E019ull) * 0xBF58476D1CE4E5B9ull ^ salt;
  h ^= h >> 31;
  h *= 0x94D049BB133111EBull;
  h ^= h >> 29;
  return double(h >> 11) * (1.0 / 9007199254740992.0);
}

// In-range indices (the common case) skip the divisions: Height() is the inner loop of every
// self-shadow march.
int Wrap(int64_t i, int n) {
  if (uint64_t(i) < uint64_t(n)) return int(i);
  const int64_t r = i % n;
  return int(r < 0 ? r + n : r);
}

// Smooth periodic value noise: `cells` lattice cells across the tile, u,v in [0,1).
double PeriodicNoise(double u, double v, int cells, uint64_t salt) {
  const double x = u * cells, y = v * cells;
  const int64_t x0 = int64_t(std::floor(x)), y0 = int64_t(std::floor(y));
  double fx = x - x0, fy = y - y0;
  fx = fx * fx * (3 - 2 * fx);
  fy = fy * fy * (3 - 2 * fy);
  auto at = [&](int64_t i, int64_t j) { return Hash01(Wrap(i, cells), Wrap(j, cells), salt); };
  const double a = at(x0, y0) + fx * (at(x0 + 1, y0) - at(x0, y0));
  const double b = at(x0, y0 + 1) + fx * (at(x0 + 1, y0 + 1) - at(x0, y0 + 1));
  return a + fy * (b - a);
}

double Fbm(double u, double v, int base_cells, int octaves, uint64_t salt) {
  double sum = 0, amp = 0.5, norm = 0;
  for (int o = 0; o < octaves; ++o) {
    sum += amp * PeriodicNoise(u, v, base_cells << o, salt + o);
    norm += amp;
    amp *= 0.5;
  }
  return sum / norm;
}

struct TexelValue {
  float height;
  Eigen::Vector3f albedo;
};

// Plain weave: warp threads along y, weft along x, each passing over and under alternately,
// with fibre twist that makes the surface anisotropic.
TexelValue Weave(double u, double v, double tile_m) {
  const int threads = 40;  // 2.4 mm pitch
  const double pitch = tile_m / threads;
  const double x = u * tile_m, y = v * tile_m;
  auto thread = [&](double across, double along, int parity, uint64_t salt, double* colour_jitter) {
    const int index = int(std::floor(across / pitch));
    const double d = (across - (index + 0.5) * pitch) / (0.46 * pitch);
    const double section = std::sqrt(std::max(0.0, 1 - d * d));
    const double undulation = std::cos(kPi * along / pitch + kPi * ((index + parity) & 1));
    const double twist = 0.5 + 0.5 * std::sin(2 * kPi * (along / (0.7 * pitch) + 1.5 * d));
    *colour_jitter = Hash01(Wrap(index, threads), 0, salt) - 0.5;
    return section > 0 ? 0.22e-3 * section + 0.16e-3 * (1 + undulation) + 0.03e-3 * twist * section : -1.0;
  };
  double jw, jf;
  const double warp = thread(x, y, 0, 11, &jw);
  const double weft = thread(y, x, 1, 23, &jf);
  const double fuzz = Fbm(u, v, 64, 3, 5);
  TexelValue t;
  if (warp < 0 && weft < 0) {
    t.height = 0.0f;
    t.albedo = Eigen::Vector3f(0.05f, 0.05f, 0.07f);
  } else if (warp >= weft) {
    t.height = float(warp + 0.02e-3 * fuzz);
    t.albedo = Eigen::Vector3f(0.10f, 0.16f, 0.42f) * float(1 + 0.25 * jw + 0.15 * (fuzz - 0.5));
  } else {
    t.height = float(weft + 0.02e-3 * fuzz);
    t.albedo = Eigen::Vector3f(0.70f, 0.62f, 0.45f) * float(1 + 0.2 * jf + 0.15 * (fuzz - 0.5));
  }
  return t;
}

// Rounded stones of varied size and colour set in dark mortar (jittered-grid Voronoi).
TexelValue Stones(double u, double v, double tile_m) {
  const int cells = 24;  // 4 mm stones
  const double x = u * cells, y = v * cells;
  const int64_t cx = int64_t(std::floor(x)), cy = int64_t(std::floor(y));
  double f1 = 1e9, f2 = 1e9;
  int64_t best_x = 0, best_y = 0;
  for (int64_t j = cy - 1; j <= cy + 1; ++j)
    for (int64_t i = cx - 1; i <= cx + 1; ++i) {
      const int wi = Wrap(i, cells), wj = Wrap(j, cells);
      const double px = i + 0.15 + 0.7 * Hash01(wi, wj, 101), py = j + 0.15 + 0.7 * Hash01(wi, wj, 202);
      const double d = std::hypot(x - px, y - py);
      if (d < f1) {
        f2 = f1;
        f1 = d;
        best_x = wi;
        best_y = wj;
      } else if (d < f2) {
        f2 = d;
      }
    }
  const double edge = (f2 - f1) * 0.5;  // distance to the cell border, in cells
  const double dome = std::sqrt(std::clamp(edge / 0.35, 0.0, 1.0));
  const double stone_height = 0.9e-3 + 0.6e-3 * Hash01(best_x, best_y, 303);
  const double grain = Fbm(u, v, 96, 3, 7);
  TexelValue t;
  t.height = float(stone_height * dome + 0.05e-3 * grain * dome);
  const double tone = Hash01(best_x, best_y, 404);
  const Eigen::Vector3f stone = Eigen::Vector3f(0.55f, 0.50f, 0.43f) * float(0.6 + 0.6 * tone) +
                                Eigen::Vector3f(0.05f, 0.02f, -0.02f) * float(Hash01(best_x, best_y, 505));
  const Eigen::Vector3f mortar(0.12f, 0.11f, 0.10f);
  const float s = float(std::clamp(edge / 0.06, 0.0, 1.0));
  t.albedo = (mortar * (1 - s) + stone * s) * float(0.85 + 0.3 * grain);
  return t;
}

// Corduroy: rounded wales along y with narrow grooves, pile fuzz and a slight colour streak.
TexelValue Corduroy(double u, double v, double tile_m) {
  const int wales = 32;  // 3 mm
  const double phase = u * wales - std::floor(u * wales);
  const double ridge = std::pow(std::sin(kPi * phase), 0.5);
  const double fuzz = Fbm(u, v * 0.25, 128, 3, 9);
  const double streak = Fbm(u, 0.0, 32, 2, 13);
  TexelValue t;
  t.height = float(1.1e-3 * ridge + 0.06e-3 * fuzz);
  const float shade = float(0.55 + 0.45 * ridge);
  t.albedo = Eigen::Vector3f(0.55f, 0.22f, 0.10f) * shade * float(0.85 + 0.3 * streak);
  return t;
}

TexelValue Flat(double, double, double) { return {0.0f, Eigen::Vector3f(0.5f, 0.5f, 0.5f)}; }

// The `ggx` material's known parameters (a GGX fit must recover them).
constexpr float kGgxBaseColor[3] = {0.62f, 0.36f, 0.18f};
constexpr double kGgxRoughness = 0.45, kGgxMetallic = 0.3;
TexelValue FlatCopper(double, double, double) {
  return {0.0f, Eigen::Vector3f(kGgxBaseColor[0], kGgxBaseColor[1], kGgxBaseColor[2])};
}

}  // namespace

StatusOr<Material> Material::Create(const std::string& name) {
  using Fn = TexelValue (*)(double, double, double);
  Fn fn = nullptr;
  Material m;
  m.name_ = name;
  if (name == "weave") {
    fn = Weave;
    m.specular_f0_ = 0.04;
    m.roughness_ = 0.35;
  } else if (name == "stones") {
    fn = Stones;
    m.specular_f0_ = 0.05;
    m.roughness_ = 0.22;
  } else if (name == "corduroy") {
    fn = Corduroy;
    m.specular_f0_ = 0.03;
    m.roughness_ = 0.5;
  } else if (name == "flat") {
    fn = Flat;
    m.specular_f0_ = 0.0;
    m.roughness_ = 1.0;
  } else if (name == "ggx") {
    fn = FlatCopper;
    m.pbr_ = true;
    m.pbr_roughness_ = kGgxRoughness;
    m.pbr_metallic_ = kGgxMetallic;
  } else {
    std::string names;
    for (const auto& info : MaterialCatalog()) names += (names.empty() ? "" : ", ") + info.name;
    return Status::Error("unknown material '" + name + "' (choose one of: " + names + ")");
  }
  const size_t n = size_t(m.grid_) * m.grid_;
  m.height_.resize(n);
  m.albedo_.resize(n);
  ParallelFor(0, m.grid_, [&](int j) {
    for (int i = 0; i < m.grid_; ++i) {
      const TexelValue t = fn((i + 0.5) / m.grid_, (j + 0.5) / m.grid_, m.tile_m_);
      m.height_[size_t(j) * m.grid_ + i] = t.height;
      m.albedo_[size_t(j) * m.grid_ + i] = t.albedo.cwiseMax(0.0f).cwiseMin(1.0f);
    }
  });
  m.FinishGrids();
  return m;
}

void Material::FinishGrids() {
  const int n = grid_;
  const double cell = cell_m();
  normal_.resize(size_t(n) * n);
  max_height_m_ = *std::max_element(height_.begin(), height_.end());
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      auto h = [&](int a, int b) { return height_[size_t(Wrap(b, n)) * n + Wrap(a, n)]; };
      const double dhdx = (h(i + 1, j) - h(i - 1, j)) / (2 * cell);
      const double dhdy = (h(i, j + 1) - h(i, j - 1)) / (2 * cell);
      normal_[size_t(j) * n + i] = Eigen::Vector3f(float(-dhdx), float(-dhdy), 1.0f).normalized();
    }
}

template <typename T, typename Fn>
T Material::Lerp(const std::vector<T>& grid, double x_m, double y_m, Fn&& get) const {
  // Grid units by one multiplication (the divisions were a fifth of a self-shadow march).
  const double per_cell = grid_ / tile_m_;
  const double gx = x_m * per_cell - 0.5, gy = y_m * per_cell - 0.5;
  const double fx0 = std::floor(gx), fy0 = std::floor(gy);
  const float ax = float(gx - fx0), ay = float(gy - fy0);
  const int x0 = Wrap(int64_t(fx0), grid_), y0 = Wrap(int64_t(fy0), grid_);
  const int x1 = x0 + 1 == grid_ ? 0 : x0 + 1, y1 = y0 + 1 == grid_ ? 0 : y0 + 1;
  const T a = get(grid[size_t(y0) * grid_ + x0]), b = get(grid[size_t(y0) * grid_ + x1]);
  const T c = get(grid[size_t(y1) * grid_ + x0]), d = get(grid[size_t(y1) * grid_ + x1]);
  const T top = a + (b - a) * ax, bottom = c + (d - c) * ax;
  return top + (bottom - top) * ay;
}

float Material::Height(double x_m, double y_m) const {
  return Lerp(height_, x_m, y_m, [](float v) { return v; });
}

Eigen::Vector3f Material::Albedo(double x_m, double y_m) const {
  return Lerp(albedo_, x_m, y_m, [](const Eigen::Vector3f& v) { return v; });
}

Eigen::Vector3f Material::Normal(double x_m, double y_m) const {
  return Lerp(normal_, x_m, y_m, [](const Eigen::Vector3f& v) { return v; }).normalized();
}

}  // namespace mesocap
