#include "synth/synth_test_support.h"

#include <algorithm>
#include <cstdio>
#include <map>
#include <mutex>
#include <random>

#include <gtest/gtest.h>

#include "capture/btf_render.h"
#include "capture/rig_material.h"
#include "capture/true_btf_folder.h"
#include "core/directions.h"
#include "core/image_io.h"
#include "core/status.h"
#include "synth/synth_quality.h"

namespace mesocap::testing {

std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> ExemplarPairs() {
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> pairs;
  for (auto [ti, pi] : {std::pair{0.0, 0.0}, {40.0, 0.0}, {40.0, 90.0}, {60.0, 210.0}})
    for (auto [to, po] : {std::pair{0.0, 0.0}, {45.0, 90.0}})
      pairs.push_back({DirectionFromAnglesDeg(ti, pi), DirectionFromAnglesDeg(to, po)});
  return pairs;
}

namespace {

// The exemplar folders this process rendered, removed when it exits.
struct RenderedFolders {
  std::vector<std::filesystem::path> folders;
  ~RenderedFolders() {
    std::error_code ec;
    for (const auto& f : folders) std::filesystem::remove_all(f, ec);
  }
};

}  // namespace

Exemplar VirtualRigExemplar(const std::string& material, int size) {
  static std::mutex mutex;
  static RenderedFolders rendered;
  std::lock_guard<std::mutex> lock(mutex);
  const auto dir = std::filesystem::temp_directory_path() /
                   ("mesocap_synth_exemplar_" + std::to_string(getpid()) + "_" + material + "_" + std::to_string(size));
  if (!std::filesystem::exists(dir / "index.json")) {
    rendered.folders.push_back(dir);
    auto m = Material::Create(material);
    MESOCAP_CHECK(m.ok(), m.status().message());
    TrueBtfFolderOptions options;
    options.size = size;
    MESOCAP_CHECK(WriteTrueBtfFolder(*m, ExemplarPairs(), options, dir).ok(), "cannot write the exemplar");
  }
  auto e = LoadExemplar(dir);
  MESOCAP_CHECK(e.ok(), e.status().message());
  return std::move(*e);
}

Image PhotoCrop(const std::string& name, int size) {
  const auto path = std::filesystem::path(MESOCAP_SOURCE_DIR) / "tests" / "data" / "textures" / (name + ".png");
  auto photo = ReadImage(path, {true, 3});
  MESOCAP_CHECK(photo.ok(), photo.status().message());
  MESOCAP_CHECK(photo->width() >= size && photo->height() >= size, path.string() + " is smaller than the crop");
  Image crop(size, size, 3);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x)
      for (int c = 0; c < 3; ++c) crop.at(x, y, c) = photo->at(x, y, c);
  return crop;
}

Image RandomTiling(const Image& image, int width, int height, uint32_t seed) {
  constexpr int kRandomTile = 24;
  return ApplyMapToImage(RandomTilingMap(image.width(), image.height(), width, height, kRandomTile, seed), image);
}

double RandomTilingSubband(const Image& image, int width, int height, uint32_t seed) {
  return SubbandDistance(RandomTiling(image, width, height, seed), image);
}

Image NoiseImage(int width, int height, int channels, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0, 1);
  Image image(width, height, channels);
  for (size_t i = 0; i < image.size(); ++i) image.data()[i] = u(rng);
  return image;
}

namespace {

// The test PTMs' 16 lights: 8 at 30 deg, 8 at 55 deg between them.
std::vector<Eigen::Vector3d> PtmLights() {
  std::vector<Eigen::Vector3d> lights;
  for (int k = 0; k < 16; ++k) lights.push_back(DirectionFromAnglesDeg(k < 8 ? 30 : 55, 45.0 * (k % 8) + (k < 8 ? 0 : 22.5)));
  return lights;
}

Ptm FitRgbPtm(const std::vector<Image>& photos, const std::vector<Eigen::Vector3d>& lights) {
  PtmFitOptions fit;
  fit.format = PtmFormat::kRgb;
  auto ptm = FitPtm(photos, lights, fit);
  MESOCAP_CHECK(ptm.ok(), ptm.status().message());
  return std::move(*ptm);
}

}  // namespace

Ptm VirtualRigPtm(const std::string& material_name, int size) {
  auto material = Material::Create(material_name);
  MESOCAP_CHECK(material.ok(), material.status().message());
  const std::vector<Eigen::Vector3d> lights = PtmLights();
  std::vector<Image> photos;
  for (const Eigen::Vector3d& light : lights)
    photos.push_back(RenderTrueBtfSlice(*material, TrueBtfRequestFor(light, Eigen::Vector3d::UnitZ(), size, 2)));
  return FitRgbPtm(photos, lights);
}

Ptm PhotoReliefPtm(const Image& photo, double relief) {
  const int w = photo.width(), h = photo.height();
  auto height = [&](int x, int y) {
    x = std::clamp(x, 0, w - 1), y = std::clamp(y, 0, h - 1);
    return relief * (0.2126 * photo.at(x, y, 0) + 0.7152 * photo.at(x, y, 1) + 0.0722 * photo.at(x, y, 2));
  };
  const std::vector<Eigen::Vector3d> lights = PtmLights();
  std::vector<Image> photos;
  for (const Eigen::Vector3d& light : lights) {
    Image lit(w, h, 3);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        // Image rows run down; the material frame's y runs up the slice.
        const Eigen::Vector3d n = Eigen::Vector3d(-(height(x + 1, y) - height(x - 1, y)) / 2,
                                                  (height(x, y + 1) - height(x, y - 1)) / 2, 1).normalized();
        const double shade = std::max(0.0, n.dot(light));
        for (int c = 0; c < 3; ++c) lit.at(x, y, c) = float(photo.at(x, y, c) * shade);
      }
    photos.push_back(std::move(lit));
  }
  return FitRgbPtm(photos, lights);
}

std::vector<Image> RelitUnderThreeLights(const Ptm& ptm) {
  std::vector<Image> relit;
  for (const Eigen::Vector3d& light : {DirectionFromAnglesDeg(0, 0), DirectionFromAnglesDeg(40, 60), DirectionFromAnglesDeg(60, 200)})
    relit.push_back(RelightPtm(ptm, light));
  return relit;
}

void ExpectGoodSeamsAndStatistics(const std::function<SynthMap(uint32_t)>& synthesize, const std::vector<Image>& slices,
                                  int block, uint32_t seed, double max_seam_ratio, double statistics_slack) {
  std::vector<double> ours(slices.size(), 0.0), random_tiling(slices.size(), 0.0);
  for (uint32_t s = seed; s < seed + 3; ++s) {
    const SynthMap map = synthesize(s);
    const SynthMap random = RandomTilingMap(map.sample_width, map.sample_height, map.width, map.height, block, s);
    for (size_t k = 0; k < slices.size(); ++k) {
      const Image out = ApplyMapToImage(map, slices[k]), tiled = ApplyMapToImage(random, slices[k]);
      const SeamMeasure seams = MeasureSeams(map, out, slices[k]), r = MeasureSeams(random, tiled, slices[k]);
      std::printf("image %zu, seed %u: seams %.3f (random placement %.3f)\n", k, s, seams.ratio(), r.ratio());
      EXPECT_GT(seams.cut_pairs, 0);
      EXPECT_LE(seams.ratio(), max_seam_ratio) << "image " << k << ", seed " << s;
      EXPECT_LT(seams.ratio(), 0.8 * r.ratio()) << "image " << k << ", seed " << s;
      ours[k] += SubbandDistance(out, slices[k]);
      random_tiling[k] += SubbandDistance(tiled, slices[k]);
    }
  }
  for (size_t k = 0; k < slices.size(); ++k) EXPECT_LT(ours[k], statistics_slack * random_tiling[k]) << "image " << k;
}

}  // namespace mesocap::testing
