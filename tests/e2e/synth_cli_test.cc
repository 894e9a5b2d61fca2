// synth, synth-apply and paint through the real CLI on a virtual-rig BTF folder and on an image.
#include <filesystem>

#include <gtest/gtest.h>

#include <cmath>

#include "core/atomic_file.h"
#include "core/image_io.h"
#include "core/json.h"
#include "formats/ptm_file.h"
#include "synth/synth_map.h"
#include "synth/synth_test_support.h"
#include "synth/texton_analysis.h"
#include "tests/testing.h"

namespace mesocap {
namespace {
namespace fs = std::filesystem;

TEST(SynthCli, QuiltAndRollerOutputsAndSynthApplyReproducesEverySlice) {
  const Exemplar e = testing::VirtualRigExemplar("weave", 64);
  const fs::path dir = testing::MakeTempDir();
  const std::string in = e.path.string();
  // Quilting's patches may hang off the sample's edge (synth/quilt.h) unless --inside-sample.
  for (auto [method, extra] : {std::pair<std::string, std::string>{"quilt", ""}, {"quilt-inside", " --inside-sample"}, {"roller", ""}}) {
    std::string log;
    const fs::path out = dir / method, applied = dir / (method + "_applied");
    const std::string name = method == "quilt-inside" ? "quilt" : method;
    ASSERT_EQ(testing::RunMesocap("synth --method " + name + extra + " --input " + in + " --size 96x80 --no-progress --out " + out.string(), &log), 0) << log;
    for (const char* f : {"map.exr", "index.json", "report.json", "patches.png", "preview_light1.png", "preview_light2.png", "preview_light3.png"})
      EXPECT_TRUE(fs::exists(out / f)) << method << " " << f;
    auto report = ReadJsonFile(out / "report.json");
    ASSERT_TRUE(report.ok());
    EXPECT_TRUE((*report)["seams"].is_array());
    EXPECT_GT((*report)["memory_peak_mib"].get<double>(), 0);
    if (name == "quilt") {
      EXPECT_EQ((*report)["parameters"]["whole_sample"], extra.empty());
    }
    ASSERT_EQ(testing::RunMesocap("synth-apply --map " + (out / "map.exr").string() + " --input " + in + " --no-progress --out " + applied.string(), &log), 0) << log;
    auto index = ReadJsonFile(out / "index.json");
    ASSERT_TRUE(index.ok());
    ASSERT_EQ((*index)["slices"].size(), e.slices.size());
    for (const auto& s : (*index)["slices"]) {
      const std::string file = s["file"].get<std::string>();
      auto a = ReadImage(out / file), b = ReadImage(applied / file);
      ASSERT_TRUE(a.ok() && b.ok()) << file;
      EXPECT_EQ(a->width(), 96);
      EXPECT_EQ(a->height(), 80);
      EXPECT_TRUE(*a == *b) << method << " " << file;  // bit for bit
    }
  }
}

// ptm-block on a .ptm: the synthesized .ptm relights as the sample's texels the map names, under
// any light (the coefficients are copied, through the Legendre basis and back); synth-apply writes
// the same file; the report gives the rejection search's figures.
TEST(SynthCli, PtmBlockSynthesisOfAPtm) {
  const fs::path dir = testing::MakeTempDir();
  Ptm ptm;
  ptm.format = PtmFormat::kRgb;
  ptm.coefficients = Image(48, 40, 18);
  for (int y = 0; y < 40; ++y)
    for (int x = 0; x < 48; ++x)
      for (int k = 0; k < 18; ++k)
        ptm.coefficients.at(x, y, k) = float(0.2 + 0.1 * std::sin(0.4 * x + 0.7 * y + k) + (k % 6 == 5 ? 0.4 : 0.0));
  ASSERT_TRUE(WritePtmFile(dir / "sample.ptm", ptm).ok());
  std::string log;
  const fs::path out = dir / "block", applied = dir / "applied";
  ASSERT_EQ(testing::RunMesocap("synth --method ptm-block --block 12 --input " + (dir / "sample.ptm").string() +
                                    " --size 70x50 --no-progress --out " + out.string(),
                                &log),
            0)
      << log;
  auto synthesized = ReadPtmFile(out / "synth.ptm"), sample = ReadPtmFile(dir / "sample.ptm");
  ASSERT_TRUE(synthesized.ok() && sample.ok()) << log;
  auto map = ReadSynthMap(out / "map.exr");
  ASSERT_TRUE(map.ok());
  EXPECT_EQ(map->method, "ptm-block");
  const Eigen::Vector3d light = Eigen::Vector3d(0.3, -0.4, 0.8).normalized();
  const Image a = RelightPtm(*synthesized, light), b = ApplyMapToImage(*map, RelightPtm(*sample, light));
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) EXPECT_NEAR(a.data()[i], b.data()[i], 2.0 / 255) << i;
  auto report = ReadJsonFile(out / "report.json");
  ASSERT_TRUE(report.ok());
  EXPECT_GT((*report)["rejected_fraction"].get<double>(), 0.5);
  EXPECT_EQ((*report)["parameters"]["block"].get<int>(), 12);
  ASSERT_EQ(testing::RunMesocap("synth-apply --map " + (out / "map.exr").string() + " --input " + (dir / "sample.ptm").string() +
                                    " --no-progress --out " + applied.string(),
                                &log),
            0)
      << log;
  auto again = ReadTextFile(applied / "synth.ptm"), first = ReadTextFile(out / "synth.ptm");
  ASSERT_TRUE(again.ok() && first.ok());
  EXPECT_TRUE(*again == *first);
}

// texton: the analysis is saved beside the map and a second run reusing it (--analysis) finds the
// same map; a saved analysis of another sample, a bad option or a sample smaller than the
// neighbourhood is refused with nothing written; too many textons for the sample are capped, said.
TEST(SynthCli, TextonSynthesisSavesItsAnalysisAndReusesIt) {
  const Exemplar e = testing::VirtualRigExemplar("weave", 64);
  const fs::path dir = testing::MakeTempDir();
  std::string log;
  const std::string common = " --input " + e.path.string() + " --size 96x80 --textons 100 --no-progress --out ";
  ASSERT_EQ(testing::RunMesocap("synth --method texton --audit 0.1" + common + (dir / "first").string(), &log), 0) << log;
  auto analysis = ReadTextonAnalysis(dir / "first" / "textons.exr");
  ASSERT_TRUE(analysis.ok()) << analysis.status().message();
  EXPECT_EQ(analysis->levels[0].textons, 100);
  EXPECT_EQ(analysis->slice_count, int(e.slices.size()));
  auto report = ReadJsonFile(dir / "first" / "report.json");
  ASSERT_TRUE(report.ok());
  EXPECT_EQ((*report)["method"], "texton");
  // The finest level's (docs/synthesis.md: the stack's lists leave out near copies, which coarse levels' full
  // searches often pick).
  EXPECT_GE((*report)["derived"]["levels"][0]["full_search_agreement"].get<double>(), 0.7);
  EXPECT_EQ((*report)["derived"]["levels"].size(), analysis->levels.size());
  ASSERT_EQ(testing::RunMesocap("synth --method texton --analysis " + (dir / "first" / "textons.exr").string() + common +
                                    (dir / "second").string(),
                                &log),
            0)
      << log;
  auto first = ReadSynthMap(dir / "first" / "map.exr"), second = ReadSynthMap(dir / "second" / "map.exr");
  ASSERT_TRUE(first.ok() && second.ok());
  EXPECT_EQ(first->method, "texton");
  EXPECT_EQ(first->source_x, second->source_x);
  EXPECT_EQ(first->source_y, second->source_y);

  Image small(20, 20, 3);
  for (int y = 0; y < 20; ++y)
    for (int x = 0; x < 20; ++x) small.at(x, y, x % 3) = float((x * 7 + y * 3) % 5) / 5;
  ASSERT_TRUE(WriteImage(dir / "small.png", small).ok());
  const std::string small_in = " --input " + (dir / "small.png").string() + " --no-progress --out ";
  EXPECT_EQ(testing::RunMesocap("synth --method texton --analysis " + (dir / "first" / "textons.exr").string() + small_in +
                                    (dir / "a").string(),
                                &log),
            1);
  EXPECT_NE(log.find("textons.exr: analyses a 64x64 sample; the exemplar is 20x20"), std::string::npos) << log;
  EXPECT_EQ(testing::RunMesocap("synth --method texton --k 0" + small_in + (dir / "b").string(), &log), 2);
  EXPECT_NE(log.find("k must be"), std::string::npos) << log;
  ASSERT_TRUE(WriteImage(dir / "tiny.png", Image(12, 12, 3, 0.5f)).ok());
  EXPECT_EQ(testing::RunMesocap("synth --method texton --neighbourhood 13 --size 30 --input " + (dir / "tiny.png").string() +
                                    " --no-progress --out " + (dir / "c").string(),
                                &log),
            1);
  EXPECT_NE(log.find("tiny.png: the sample (12x12) is smaller than the 13x13 neighbourhood"), std::string::npos) << log;
  for (const char* f : {"a", "b", "c"}) EXPECT_FALSE(fs::exists(dir / f)) << f;
  ASSERT_EQ(testing::RunMesocap("synth --method texton --textons 1000 --size 30" + small_in + (dir / "d").string(), &log), 0)
      << log;
  EXPECT_NE(log.find("n_t = 1000 is more than the sample's texels allow: 400 textons"), std::string::npos) << log;
}

TEST(SynthCli, BadInputsGiveOneLineTheRightCodeAndNoOutput) {
  const fs::path dir = testing::MakeTempDir();
  Image small(20, 20, 3, 0.5f);
  ASSERT_TRUE(WriteImage(dir / "small.png", small).ok());
  std::string log;
  EXPECT_EQ(testing::RunMesocap("synth --method texture-magic --input " + (dir / "small.png").string() + " --out " + (dir / "a").string(), &log), 2);
  EXPECT_NE(log.find("unknown method"), std::string::npos) << log;
  EXPECT_EQ(testing::RunMesocap("synth --method quilt --patch-radius 16 --input " + (dir / "small.png").string() + " --no-progress --out " + (dir / "b").string(), &log), 1);
  EXPECT_NE(log.find("small.png"), std::string::npos) << log;
  EXPECT_NE(log.find("smaller than the work patch"), std::string::npos) << log;
  EXPECT_EQ(testing::RunMesocap("synth --input " + (dir / "missing.exr").string() + " --no-progress --out " + (dir / "c").string(), &log), 1);
  EXPECT_NE(log.find("missing.exr"), std::string::npos) << log;
  EXPECT_EQ(testing::RunMesocap("synth --input " + (dir / "small.png").string() + " --size 12xq --out " + (dir / "d").string(), &log), 2);
  Image mask(20, 20, 1, 0.f);
  ASSERT_TRUE(WriteImage(dir / "empty_mask.png", mask).ok());
  EXPECT_EQ(testing::RunMesocap("paint --input " + (dir / "small.png").string() + " --feature-mask " + (dir / "empty_mask.png").string() +
                                " --target-mask " + (dir / "empty_mask.png").string() + " --size 20x20 --no-progress --out " + (dir / "e").string(), &log), 1);
  EXPECT_NE(log.find("feature mask marks no texel"), std::string::npos) << log;
  EXPECT_EQ(testing::RunMesocap("paint --input " + (dir / "small.png").string() + " --feature-mask " + (dir / "empty_mask.png").string() +
                                " --target-mask " + (dir / "empty_mask.png").string() + " --size 40x40 --no-progress --out " + (dir / "f").string(), &log), 1);
  EXPECT_NE(log.find("--size is 40x40"), std::string::npos) << log;
  for (const char* f : {"a", "b", "c", "d", "e", "f"}) EXPECT_FALSE(fs::exists(dir / f)) << f;
  for (const auto& entry : fs::directory_iterator(dir)) EXPECT_EQ(entry.path().filename().string().find(".partial"), std::string::npos);
}

TEST(SynthCli, ImageExemplarWritesTheSynthesizedImage) {
  const fs::path dir = testing::MakeTempDir();
  Image image(48, 48, 3);
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 48; ++x)
      for (int c = 0; c < 3; ++c) image.at(x, y, c) = float(((x / 6 + y / 6) % 2) * 0.5 + 0.1 * c);
  ASSERT_TRUE(WriteImage(dir / "checks.png", image).ok());
  std::string log;
  ASSERT_EQ(testing::RunMesocap("synth --input " + (dir / "checks.png").string() + " --size 100 --no-progress --out " + (dir / "q").string(), &log), 0) << log;
  auto out = ReadImage(dir / "q" / "synth.exr");
  ASSERT_TRUE(out.ok());
  EXPECT_EQ(out->width(), 100);
  EXPECT_TRUE(fs::exists(dir / "q" / "preview.png"));
}

}  // namespace
}  // namespace mesocap
