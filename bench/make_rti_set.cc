// bench_make_rti_set OUT_DIR [N=36] [W=2000] [H=1500] [GRAIN=0]: writes N JPEGs of a synthetic
// Lambertian surface (bumps + colour texture) lit from N hemisphere directions, and
// OUT_DIR/capture.lp. GRAIN > 0 adds a fixed per-pixel albedo texture of that relative amplitude
// plus per-photo sensor noise, so the JPEGs have the detail (and size, about 1 MB at 0.1) of real
// photos; GRAIN = 0 gives smooth images that compress to about 0.2 MB and decode faster.
#include <algorithm>
#include <atomic>
#include <cstdint>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <numbers>
#include <string>
#include <vector>

#include "core/image_io.h"
#include "core/parallel.h"
#include "formats/lp_file.h"

int main(int argc, char** argv) {
  using namespace mesocap;
  if (argc < 2) {
    std::fprintf(stderr, "usage: bench_make_rti_set OUT_DIR [N] [W] [H] [GRAIN]\n");
    return 2;
  }
  const std::filesystem::path dir = argv[1];
  const int n = argc > 2 ? std::atoi(argv[2]) : 36, w = argc > 3 ? std::atoi(argv[3]) : 2000,
            h = argc > 4 ? std::atoi(argv[4]) : 1500;
  const float grain = argc > 5 ? float(std::atof(argv[5])) : 0.0f;
  // A reproducible hash to [-1, 1), for texture and noise without a shared generator.
  auto hash = [](uint64_t x) {
    x ^= x >> 33;
    x *= 0xff51afd7ed558ccdULL;
    x ^= x >> 33;
    x *= 0xc4ceb9fe1a85ec53ULL;
    x ^= x >> 33;
    return float(x >> 40) / float(1 << 23) - 1.0f;
  };
  std::filesystem::create_directories(dir);
  // Per-pixel normal and albedo, computed once.
  std::vector<float> normal(size_t(w) * h * 3), albedo(size_t(w) * h * 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const double u = 2 * std::numbers::pi * x / 250.0, v = 2 * std::numbers::pi * y / 250.0;
      double nx = -0.3 * std::cos(u) * std::sin(v), ny = 0.3 * std::sin(u) * std::cos(v), nz = 1;
      const double len = std::sqrt(nx * nx + ny * ny + nz * nz);
      float* nn = &normal[(size_t(y) * w + x) * 3];
      nn[0] = float(nx / len), nn[1] = float(ny / len), nn[2] = float(nz / len);
      float* a = &albedo[(size_t(y) * w + x) * 3];
      a[0] = float(0.4 + 0.3 * x / w), a[1] = float(0.5 + 0.2 * std::sin(x * 0.05)), a[2] = float(0.3 + 0.4 * y / h);
      if (grain > 0) {
        const float t = 1 + grain * hash(uint64_t(y) * w + x);
        for (int c = 0; c < 3; ++c) a[c] *= t * (1 + 0.3f * grain * hash((uint64_t(y) * w + x) * 3 + c + (1ULL << 40)));
      }
    }
  std::vector<LpEntry> entries(n);
  for (int i = 0; i < n; ++i) {
    const double elev = (25 + 55.0 * (i % 4) / 3) * std::numbers::pi / 180;
    const double az = 2 * std::numbers::pi * i / n;
    entries[i].light_dir = {std::cos(elev) * std::cos(az), std::cos(elev) * std::sin(az), std::sin(elev)};
    char name[32];
    std::snprintf(name, sizeof name, "img_%03d.jpg", i);
    entries[i].image = dir / name;
  }
  std::atomic<int> failures{0};
  ParallelFor(0, n, [&](int i) {
    const Eigen::Vector3d l = entries[i].light_dir;
    Image img(w, h, 3);
    for (size_t p = 0; p < size_t(w) * h; ++p) {
      const float* nn = &normal[p * 3];
      const float shade = std::max(0.f, float(nn[0] * l.x() + nn[1] * l.y() + nn[2] * l.z()));
      // Stored values: WriteImage sRGB-encodes 8-bit output, so hand it the decoded value.
      for (int c = 0; c < 3; ++c) {
        float v = albedo[p * 3 + c] * shade;
        if (grain > 0) v += 0.1f * grain * hash((uint64_t(i) << 48) ^ (p * 3 + c) ^ (1ULL << 47));
        img.data()[p * 3 + c] = SrgbToLinear(std::clamp(v, 0.f, 1.f));
      }
    }
    ImageWriteOptions o;
    o.format = PixelFormat::kUint8Srgb;
    o.jpeg_quality = 92;
    if (!WriteImage(entries[i].image, img, o).ok()) ++failures;
  });
  if (failures.load() || !WriteLpFile(dir / "capture.lp", entries).ok()) {
    std::fprintf(stderr, "bench_make_rti_set: failed to write %s\n", dir.c_str());
    return 1;
  }
  std::printf("%s: %d JPEGs %dx%d + capture.lp\n", dir.c_str(), n, w, h);
  return 0;
}
