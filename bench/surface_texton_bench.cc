// Surface texton synthesis (mesh/surface_textons.h) against the plane method it carries onto
// meshes: on a flat grid mesh (one vertex per texel, frames along x) the surface map is an image
// map, so the plane's measures apply. Prints, per corpus photograph: seams (cut step / the
// sample's neighbour step), subband and Laplacian/gradient distances as ratios to random tiling's
// (24-texel patches), for the plane method and the surface method, and the surface method's time.
// Usage: bench_surface_textons [--size 256] [--crop 96] [--out DIR] [texture ...]
// (textures from tests/data/textures, default: brick bark sand leaves woodgrain stones).
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "core/image_io.h"
#include "mesh/surface_textons.h"
#include "synth/exemplar.h"
#include "synth/synth_quality.h"
#include "synth/texton_synthesis.h"

using namespace mesocap;

namespace {

TriangleMesh Grid(int n) {
  TriangleMesh m;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) m.positions.emplace_back(x, -y, 0), m.normals.emplace_back(0, 0, 1);
  auto at = [n](int x, int y) { return int32_t(y * n + x); };
  for (int y = 0; y + 1 < n; ++y)
    for (int x = 0; x + 1 < n; ++x) {
      m.faces.push_back({at(x, y + 1), at(x + 1, y + 1), at(x + 1, y)});
      m.faces.push_back({at(x, y + 1), at(x + 1, y), at(x, y)});
    }
  return m;
}

struct Scores {
  double seams = 0, subband = 0, laplacian = 0;
};

// The map's interior, a margin of an eighth of its side left out on every side: the grid mesh has
// a border (slots beyond it take the default texton) where the plane's output wraps around.
SynthMap Interior(const SynthMap& map) {
  const int m = map.width / 8, w = map.width - 2 * m, h = map.height - 2 * m;
  SynthMap out(w, h, map.sample_width, map.sample_height, map.method);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = map.index(x + m, y + m);
      out.Set(x, y, map.source_x[i], map.source_y[i], map.rotation_deg[i], map.patch[i]);
    }
  return out;
}

Scores Score(const SynthMap& whole, const Image& sample) {
  const SynthMap map = Interior(whole);
  const Image out = ApplyMapToImage(map, sample);
  return {MeasureSeams(map, out, sample).ratio(), SubbandDistance(out, sample), LaplacianGradientDistance(out, sample)};
}

}  // namespace

int main(int argc, char** argv) {
  int size = 256, crop = 96;
  std::filesystem::path out_dir;
  std::vector<std::string> textures;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--size") && i + 1 < argc) size = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--crop") && i + 1 < argc) crop = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--out") && i + 1 < argc) out_dir = argv[++i];
    else textures.push_back(argv[i]);
  }
  if (textures.empty()) textures = {"brick", "bark", "sand", "leaves", "woodgrain", "stones"};
  const TriangleMesh grid = Grid(size);
  TangentFrames frames = FramesFromDirections(grid, std::vector<Eigen::Vector3d>(grid.vertex_count(), Eigen::Vector3d::UnitX()));
  std::printf("%-10s | %-22s | %-22s | %s\n", "texture", "plane seams/sub/lap", "surface seams/sub/lap", "surface s");
  for (const std::string& name : textures) {
    const auto path = std::filesystem::path(MESOCAP_SOURCE_DIR) / "tests" / "data" / "textures" / (name + ".png");
    auto photo = ReadImage(path, {true, 3});
    if (!photo.ok()) return std::fprintf(stderr, "%s\n", photo.status().message().c_str()), 1;
    Image sample(crop, crop, 3);
    for (int y = 0; y < crop; ++y)
      for (int x = 0; x < crop; ++x)
        for (int c = 0; c < 3; ++c) sample.at(x, y, c) = photo->at(x, y, c);
    const Exemplar e = ImageExemplar(sample);
    auto analysis = AnalyzeTextons(AppearanceImageCount(e), [&](int k) { return AppearanceLuminance(e, k); }, {});
    if (!analysis.ok()) return 1;
    const Scores random = Score(RandomTilingMap(crop, crop, size, size, 24, 1), sample);
    TextonSynthesisOptions po;
    po.width = po.height = size;
    const Scores plane = Score(*TextonSynthesis(*analysis, po, nullptr), sample);
    const auto start = std::chrono::steady_clock::now();
    SurfaceTextonOptions so;
    so.texel_size = 1;
    auto surface = SurfaceTextonSynthesis(grid, frames, *analysis, so, nullptr);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (!surface.ok()) return std::fprintf(stderr, "%s\n", surface.status().message().c_str()), 1;
    SynthMap map(size, size, crop, crop, "texton");
    for (int v = 0; v < grid.vertex_count(); ++v) map.Set(v % size, v / size, surface->source_x[v], surface->source_y[v], 0, 0);
    map.patch = CoherentRegions(map);
    const Scores s = Score(map, sample);
    std::printf("%-10s | %5.2f %5.2fx %5.2fx   | %5.2f %5.2fx %5.2fx   | %.1f\n", name.c_str(), plane.seams, plane.subband / random.subband,
                plane.laplacian / random.laplacian, s.seams, s.subband / random.subband, s.laplacian / random.laplacian, seconds);
    if (!out_dir.empty()) {
      std::filesystem::create_directories(out_dir);
      WriteImage(out_dir / (name + "_surface.png"), ApplyMapToImage(map, sample));
    }
  }
  return 0;
}
