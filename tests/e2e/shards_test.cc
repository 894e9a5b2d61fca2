// Sharded stages through the real CLI (docs/workflow.md): stage by stage (`process --stage`),
// reconstruct shards merged for N = 1, 3 and 7 equal one unsharded run (every slice's pixels, the
// index's entries and figures, timings and provenance aside), the statistics computed once; the
// synth stage's map application and the export's GGX fit in 3 shards equal theirs; a missing shard stops the merge with a message naming it and nothing published;
// a shard whose part is done is not redone; a changed option gives the parts a new key.
#include <gtest/gtest.h>

#include <cstring>
#include <map>

#include "core/atomic_file.h"
#include "core/image_io.h"
#include "core/json.h"
#include "tests/testing.h"

namespace mesocap {
namespace {

namespace fs = std::filesystem;

std::string Options(const fs::path& session) {
  return " --camera " + (session / "truth.json").string() +
         " --slice-size 32 --btf-grid coarse --btf-size 32 --no-progress";
}

class ShardsTest : public ::testing::Test {
 protected:
  // One rendered session, processed whole once: the reference every sharded run must equal.
  static void SetUpTestSuite() {
    const fs::path root = testing::MakeTempDir();
    rendered_ = new fs::path(root / "rendered");
    whole_ = new fs::path(root / "whole");
    std::string out;
    ASSERT_EQ(testing::RunMesocap("simulate --out " + rendered_->string() +
                                      " --shots 10 --calib-shots 0 --width 1500 --height 1000 --no-progress", &out), 0) << out;
    fs::copy(*rendered_, *whole_, fs::copy_options::recursive);
    ASSERT_EQ(testing::RunMesocap("process " + whole_->string() + Options(*whole_), &out), 0) << out;
  }
  static void TearDownTestSuite() { delete rendered_, delete whole_; }

  // A copy of the rendered session with the stages before reconstruct run one by one.
  static fs::path SessionBeforeReconstruct(const std::string& name) {
    const fs::path session = testing::MakeTempDir() / name;
    fs::copy(*rendered_, session, fs::copy_options::recursive);
    for (const char* stage : {"calibrate", "resample", "fit-ptm"}) {
      std::string out;
      EXPECT_EQ(testing::RunMesocap("process " + session.string() + " --stage " + stage + Options(session), &out), 0) << out;
      EXPECT_NE(out.find(std::string(stage) + " "), std::string::npos) << out;
    }
    return session;
  }

  static int Stage(const fs::path& session, const std::string& args, std::string* out) {
    return testing::RunMesocap("process " + session.string() + " --stage reconstruct " + args + Options(session), out);
  }

  static fs::path* rendered_;
  static fs::path* whole_;
};
fs::path* ShardsTest::rendered_ = nullptr;
fs::path* ShardsTest::whole_ = nullptr;

// index.json without what differs between two runs of the same stage (in two session folders).
Json WithoutTimings(Json index) {
  for (const char* field : {"seconds_statistics", "seconds_reconstruct", "ms_per_slice", "provenance", "exemplar"})
    index.erase(field);
  return index;
}

void ExpectSamePixels(const fs::path& expected, const fs::path& actual) {
  auto x = ReadImage(expected), y = ReadImage(actual);
  ASSERT_TRUE(x.ok() && y.ok()) << actual;
  ASSERT_EQ(x->size(), y->size()) << actual;
  EXPECT_EQ(std::memcmp(x->data(), y->data(), x->size() * sizeof(float)), 0) << actual;
}

// The BTF folders' indexes (timings and provenance aside) and every slice's pixels.
void ExpectSameSlices(const fs::path& expected, const fs::path& actual) {
  auto a = ReadJsonFile(expected / "index.json"), b = ReadJsonFile(actual / "index.json");
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_TRUE(WithoutTimings(*a) == WithoutTimings(*b)) << actual;
  for (const Json& entry : (*a)["slices"]) ExpectSamePixels(expected / entry["file"].get<std::string>(), actual / entry["file"].get<std::string>());
}

void ExpectSameBtf(const fs::path& expected, const fs::path& actual) {
  ExpectSameSlices(expected, actual);
  auto a = ReadJsonFile(expected / "index.json");
  ASSERT_TRUE(a.ok());
  EXPECT_EQ((*a)["slices"].size(), 289u);
}

TEST_F(ShardsTest, ShardsMergedEqualOneUnshardedRunForOneThreeAndSevenShards) {
  for (const int count : {1, 3, 7}) {
    const fs::path session = SessionBeforeReconstruct("shards" + std::to_string(count));
    std::string out;
    for (int index = 1; index <= count; ++index) {
      const std::string shard = std::to_string(index) + "/" + std::to_string(count);
      ASSERT_EQ(Stage(session, "--shard " + shard, &out), 0) << out;
      EXPECT_NE(out.find("shard " + shard + " ran"), std::string::npos) << out;
      // The statistics are computed once, by the first shard, and shared.
      EXPECT_NE(out.find(index == 1 ? "statistics computed" : "statistics shared by the first shard"), std::string::npos)
          << out;
      // Shards record nothing: the stage is done only once merged.
      EXPECT_FALSE(fs::exists(session / "btf")) << shard;
    }
    ASSERT_EQ(Stage(session, "--merge " + std::to_string(count), &out), 0) << out;
    EXPECT_NE(out.find("reconstruct  ran"), std::string::npos) << out;
    ExpectSameBtf(*whole_ / "btf", session / "btf");
    EXPECT_FALSE(fs::exists(session / "shards" / "reconstruct")) << "the merge removes the parts";
    // Recorded as the stage: the next whole run skips it and runs only the export (with another
    // thread count, which changes no output and so no stage's key).
    ASSERT_EQ(testing::RunMesocap("process " + session.string() + Options(session) + " --threads 1", &out), 0) << out;
    for (const char* stage : {"calibrate", "resample", "fit-ptm", "reconstruct"})
      EXPECT_NE(out.find(std::string(stage) + std::string(12 - std::strlen(stage), ' ') + " skipped"), std::string::npos)
          << stage << ": " << out;
    EXPECT_NE(out.find("export       ran"), std::string::npos) << out;
    for (const char* texture : {"base_color.png", "metallic_roughness.png", "normal.png"}) {
      auto a = ReadTextFile(*whole_ / "export" / "gltf" / texture), b = ReadTextFile(session / "export" / "gltf" / texture);
      ASSERT_TRUE(a.ok() && b.ok()) << texture;
      EXPECT_TRUE(*a == *b) << texture;
    }
  }
}

// The synth stage's map applied in 3 shards equals one run's folder: the map, every slice's pixels,
// the index, the previews and the report's figures.
TEST_F(ShardsTest, SynthShardsMergedEqualOneUnshardedRun) {
  const std::string synth = " --synth quilt --synth-size 64x64";
  const fs::path whole = testing::MakeTempDir() / "synth_whole", sharded = whole.parent_path() / "synth_sharded";
  fs::copy(*whole_, whole, fs::copy_options::recursive);
  fs::copy(*whole_, sharded, fs::copy_options::recursive);
  std::string out;
  ASSERT_EQ(testing::RunMesocap("process " + whole.string() + " --stage synth" + Options(whole) + synth, &out), 0) << out;
  for (int index = 1; index <= 3; ++index) {
    const std::string shard = std::to_string(index) + "/3";
    ASSERT_EQ(testing::RunMesocap("process " + sharded.string() + " --stage synth --shard " + shard + Options(sharded) + synth,
                                  &out), 0) << out;
    EXPECT_NE(out.find(index == 1 ? "the map made (shared" : "the map made by the first shard"), std::string::npos) << out;
  }
  ASSERT_EQ(testing::RunMesocap("process " + sharded.string() + " --stage synth --merge 3" + Options(sharded) + synth, &out), 0)
      << out;
  const fs::path a = whole / "synth", b = sharded / "synth";
  auto index_a = ReadJsonFile(a / "index.json"), index_b = ReadJsonFile(b / "index.json");
  ASSERT_TRUE(index_a.ok() && index_b.ok());
  EXPECT_EQ((*index_a)["slices"].size(), 289u);
  ExpectSameSlices(a, b);
  for (const char* picture : {"map.exr", "patches.png", "preview_light1.png", "preview_light2.png", "preview_light3.png"})
    ExpectSamePixels(a / picture, b / picture);
  auto report_a = ReadJsonFile(a / "report.json"), report_b = ReadJsonFile(b / "report.json");
  ASSERT_TRUE(report_a.ok() && report_b.ok());
  (*report_a)["exemplar"].erase("path"), (*report_b)["exemplar"].erase("path");  // the sessions' folders differ
  for (const char* field : {"seams", "output", "exemplar", "method", "parameters"})
    EXPECT_EQ((*report_a)[field], (*report_b)[field]) << field;
  EXPECT_FALSE(fs::exists(sharded / "shards" / "synth"));
}

// The export's GGX fit in 3 bands of rows, merged: the glTF textures are the unsharded export's
// bytes, the fit's error map its pixels, the fit's figures its own.
TEST_F(ShardsTest, GgxFitShardsMergedEqualOneUnshardedExport) {
  const fs::path session = SessionBeforeReconstruct("ggx");
  std::string out;
  ASSERT_EQ(Stage(session, "", &out), 0) << out;
  for (int index = 1; index <= 3; ++index) {
    const std::string shard = std::to_string(index) + "/3";
    ASSERT_EQ(testing::RunMesocap("process " + session.string() + " --stage export --shard " + shard + Options(session), &out), 0)
        << out;
    EXPECT_NE(out.find("GGX fit of rows"), std::string::npos) << out;
    // The slices are decoded once, by the first shard; the others read their band of its table.
    EXPECT_NE(out.find(index == 1 ? "the slices read (shared" : "the slices read by the first shard"), std::string::npos)
        << out;
    EXPECT_FALSE(fs::exists(session / "export")) << shard;
  }
  ASSERT_EQ(testing::RunMesocap("process " + session.string() + " --stage export --merge 3" + Options(session), &out), 0) << out;
  const fs::path a = *whole_ / "export" / "gltf", b = session / "export" / "gltf";
  for (const char* texture : {"base_color.png", "metallic_roughness.png", "normal.png", "fit_error.png"}) {
    auto x = ReadTextFile(a / texture), y = ReadTextFile(b / texture);
    ASSERT_TRUE(x.ok() && y.ok()) << texture;
    EXPECT_TRUE(*x == *y) << texture;
  }
  ExpectSamePixels(a / "fit_error.exr", b / "fit_error.exr");
  auto fit_a = ReadJsonFile(a / "fit.json"), fit_b = ReadJsonFile(b / "fit.json");
  ASSERT_TRUE(fit_a.ok() && fit_b.ok());
  fit_a->erase("seconds"), fit_b->erase("seconds");
  EXPECT_EQ(*fit_a, *fit_b);
  EXPECT_FALSE(fs::exists(session / "shards" / "export"));
  // Recorded as the stage: a whole run finds everything current.
  ASSERT_EQ(testing::RunMesocap("process " + session.string() + Options(session), &out), 0) << out;
  EXPECT_NE(out.find("export       skipped"), std::string::npos) << out;
}

TEST_F(ShardsTest, AMissingShardStopsTheMergeWithItsNameAndNothingPublished) {
  const fs::path session = SessionBeforeReconstruct("missing");
  std::string out;
  ASSERT_EQ(Stage(session, "--shard 1/3", &out), 0) << out;
  ASSERT_EQ(Stage(session, "--shard 3/3", &out), 0) << out;
  EXPECT_EQ(Stage(session, "--merge 3", &out), 1);
  EXPECT_NE(out.find("shard 2/3"), std::string::npos) << out;
  EXPECT_NE(out.find("--shard 2/3"), std::string::npos) << "says how to make it: " << out;
  EXPECT_EQ(out.find("shard 1/3 ("), std::string::npos) << "names only the missing one: " << out;
  EXPECT_FALSE(fs::exists(session / "btf"));
  // A shard already done is not redone; the missing one then completes the merge.
  ASSERT_EQ(Stage(session, "--shard 1/3", &out), 0) << out;
  EXPECT_NE(out.find("shard 1/3 done before"), std::string::npos) << out;
  ASSERT_EQ(Stage(session, "--shard 2/3", &out), 0) << out;
  ASSERT_EQ(Stage(session, "--merge 3", &out), 0) << out;
  ExpectSameBtf(*whole_ / "btf", session / "btf");
  // Merged and current: another shard run or merge finishes at once.
  ASSERT_EQ(Stage(session, "--shard 2/3", &out), 0) << out;
  EXPECT_NE(out.find("unchanged, skipped"), std::string::npos) << out;
}

TEST_F(ShardsTest, AChangedOptionGivesThePartsANewKey) {
  const fs::path session = SessionBeforeReconstruct("key");
  std::string out;
  ASSERT_EQ(Stage(session, "--shard 1/2", &out), 0) << out;
  ASSERT_EQ(testing::RunMesocap("process " + session.string() + " --stage reconstruct --shard 2/2" + Options(session) +
                                    " --btf-pixel-only", &out), 0) << out;
  // Shard 2 of the first options is missing: the parts made with other options do not count.
  EXPECT_EQ(Stage(session, "--merge 2", &out), 1);
  EXPECT_NE(out.find("shard 2/2"), std::string::npos) << out;
  int keys = 0;
  for (const auto& entry : fs::directory_iterator(session / "shards" / "reconstruct")) keys += entry.is_directory();
  EXPECT_EQ(keys, 2);
}

TEST_F(ShardsTest, ShardOptionsAreCheckedBeforeAnythingRuns) {
  const fs::path session = testing::MakeTempDir() / "usage";
  fs::copy(*rendered_, session, fs::copy_options::recursive);
  const std::string s = session.string();
  for (const auto& [args, says] : std::map<std::string, std::string>{
           {" --stage reconstruct --shard 0/3", "is not I/N"},
           {" --stage reconstruct --shard 4/3", "is not I/N"},
           {" --stage reconstruct --shard 1/3 --merge 3", "not both"},
           {" --stage fit-ptm --shard 1/3", "shardable"},
           {" --stage calibrate --merge 2", "shardable"},
           {" --shard 1/3", "shardable"},
           {" --stage tidy", "no such stage"},
           {" --stage synth", "--synth METHOD"}}) {
    std::string out;
    EXPECT_EQ(testing::RunMesocap("process " + s + args, &out), 2) << args << ": " << out;
    EXPECT_NE(out.find(says), std::string::npos) << args << ": " << out;
  }
  EXPECT_FALSE(fs::exists(session / "stages.json"));
}

}  // namespace
}  // namespace mesocap
