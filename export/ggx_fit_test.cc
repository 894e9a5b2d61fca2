// The GGX fit against the virtual rig's `ggx` material (rendered with known glTF parameters),
// and the glTF asset written from it.
#include "export/ggx_fit.h"

#include <gtest/gtest.h>

#include "capture/true_btf_folder.h"
#include "core/directions.h"
#include "core/image_io.h"
#include "export/gltf_material.h"
#include "reconstruct/statistical_btf.h"
#include "tests/testing.h"

namespace mesocap {
namespace {

namespace fs = std::filesystem;

// The true BTF of `material` at 16 texels over every light with 13 views like the rig's.
fs::path RenderTrueBtf(const std::string& material_name) {
  const fs::path dir = testing::MakeTempDir() / "btf";
  auto material = Material::Create(material_name);
  EXPECT_TRUE(material.ok());
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> pairs;
  std::vector<Eigen::Vector3d> views = {Eigen::Vector3d::UnitZ()};
  for (int k = 0; k < 4; ++k) views.push_back(DirectionFromAnglesDeg(30, 90.0 * k + 45));
  for (int k = 0; k < 8; ++k) views.push_back(DirectionFromAnglesDeg(60, 45.0 * k));
  for (const Eigen::Vector3d& view : views)
    for (const Eigen::Vector3d& light : BonnDirections()) pairs.push_back({light, view});
  TrueBtfFolderOptions options;
  options.size = 16;
  options.samples_per_axis = 1;
  EXPECT_TRUE(WriteTrueBtfFolder(*material, pairs, options, dir).ok());
  return dir / "index.json";
}

TEST(GgxFit, RecoversTheParametersTheRigRenderedWith) {
  const fs::path index = RenderTrueBtf("ggx");
  GgxFitOptions options;
  auto maps = FitGgxMaterial(index, options);
  ASSERT_TRUE(maps.ok()) << maps.status().message();
  std::printf("%s\n", maps->ToJson().dump().c_str());
  // The rig's ggx material: base colour (0.62, 0.36, 0.18), roughness 0.45, metallic 0.3, flat.
  const float base[3] = {0.62f, 0.36f, 0.18f};
  for (int y = 0; y < maps->base_color.height(); ++y)
    for (int x = 0; x < maps->base_color.width(); ++x) {
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(maps->base_color.at(x, y, c), base[c], 2.0 / 255) << x << "," << y;
      EXPECT_NEAR(maps->roughness.at(x, y, 0), 0.45, 0.05 * 0.45);
      EXPECT_NEAR(maps->metallic.at(x, y, 0), 0.3, 0.02);
      EXPECT_GT(maps->normal.at(x, y, 2), 0.9999f);
    }
  EXPECT_LT(maps->median_relative_error, 0.01);
}

TEST(GgxFit, ATexturedMaterialGetsAnErrorMapAndAGltfAsset) {
  const fs::path index = RenderTrueBtf("weave");
  GgxFitOptions options;
  options.max_slices = 120;
  auto maps = FitGgxMaterial(index, options);
  ASSERT_TRUE(maps.ok()) << maps.status().message();
  std::printf("%s\n", maps->ToJson().dump().c_str());
  // Cast shadows and masking are beyond a BRDF: reported, and bounded.
  EXPECT_GT(maps->median_relative_error, 0.0);
  EXPECT_LT(maps->median_relative_error, 0.6);
  for (size_t i = 0; i < maps->base_color.size(); ++i) {
    EXPECT_GE(maps->base_color.data()[i], 0.0f);
    EXPECT_LE(maps->base_color.data()[i], 1.0f);
  }
  // Every texel's parameters inside their bounds (steps are projected onto them).
  for (size_t i = 0; i < maps->roughness.size(); ++i) {
    EXPECT_GE(maps->roughness.data()[i], 0.05f);
    EXPECT_LE(maps->roughness.data()[i], 1.0f);
    EXPECT_GE(maps->metallic.data()[i], 0.0f);
    EXPECT_LE(maps->metallic.data()[i], 1.0f);
  }
  const fs::path out = testing::MakeTempDir();
  ASSERT_TRUE(WriteGltfMaterial({out}, *maps).ok());
  for (const char* file : {"material.gltf", "material.bin", "base_color.png", "metallic_roughness.png", "normal.png"})
    EXPECT_TRUE(fs::exists(out / file)) << file;
  std::string report;
  EXPECT_EQ(testing::ValidateGltf(out / "material.gltf", &report), 0) << report;
  std::printf("gltf-validator: %s\n", report.c_str());
  // The textures decode back to the maps within their 8-bit steps, and relight alike.
  auto back = ReadGltfMaterialTextures({out});
  ASSERT_TRUE(back.ok()) << back.status().message();
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x) {
      EXPECT_NEAR(back->roughness.at(x, y, 0), maps->roughness.at(x, y, 0), 0.5 / 255 + 1e-6);
      EXPECT_NEAR(back->metallic.at(x, y, 0), maps->metallic.at(x, y, 0), 0.5 / 255 + 1e-6);
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(back->base_color.at(x, y, c), maps->base_color.at(x, y, c), 0.01);
        EXPECT_NEAR(back->normal.at(x, y, c), maps->normal.at(x, y, c), 0.01);
      }
    }
  const Eigen::Vector3d light = DirectionFromAnglesDeg(40, 30), view = DirectionFromAnglesDeg(20, 200);
  const Image a = RelightPbrMaterial(*maps, light, view), b = RelightPbrMaterial(*back, light, view);
  double diff = 0, sum = 0;
  for (size_t i = 0; i < a.size(); ++i) diff += std::pow(a.data()[i] - b.data()[i], 2), sum += std::pow(a.data()[i], 2);
  EXPECT_LT(std::sqrt(diff / sum), 0.02);
}

TEST(GgxFit, TooFewSlicesIsAnErrorNamingTheIndex) {
  const fs::path dir = testing::MakeTempDir() / "btf";
  auto material = Material::Create("ggx");
  ASSERT_TRUE(material.ok());
  TrueBtfFolderOptions options;
  options.size = 8;
  ASSERT_TRUE(WriteTrueBtfFolder(*material, {{Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitZ()}}, options, dir).ok());
  auto maps = FitGgxMaterial(dir / "index.json", {});
  ASSERT_FALSE(maps.ok());
  EXPECT_NE(maps.status().message().find("index.json"), std::string::npos) << maps.status().message();
}

}  // namespace
}  // namespace mesocap
