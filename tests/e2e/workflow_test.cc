// The Snakemake workflow (workflow/Snakefile, docs/workflow.md) on three small virtual sessions,
// run locally: its outputs equal `mesocap process` on each session alone (the .ptm bytes, every
// pixel of every measured and reconstructed slice, the index entries, the glTF textures); a
// broken session among them fails with its reason while the others complete; after kill -9 of
// Snakemake and of the stages it was running, a rerun completes without redoing a finished stage.
#include <gtest/gtest.h>

#include <chrono>
#include <cstring>
#include <thread>

#include "core/atomic_file.h"
#include "core/image_io.h"
#include "core/json.h"
#include "tests/testing.h"

namespace mesocap {
namespace {

namespace fs = std::filesystem;

constexpr const char* kProcessOptions = "--camera {session}/truth.json --slice-size 32 --btf-grid coarse --btf-size 32";
const char* const kSessions[] = {"weave", "stones", "corduroy"};

std::string Quoted(const std::string& text) { return "'" + text + "'"; }

class WorkflowTest : public ::testing::Test {
 protected:
  // Three rendered sessions, and each processed alone by `mesocap process`: the reference.
  static void SetUpTestSuite() {
    const fs::path root = testing::MakeTempDir();
    rendered_ = new fs::path(root / "rendered");
    reference_ = new fs::path(root / "reference");
    fs::create_directories(*reference_);
    for (const char* material : kSessions) {
      std::string out;
      const fs::path session = *rendered_ / material;
      ASSERT_EQ(testing::RunMesocap("simulate --out " + session.string() + " --material " + material +
                                        " --shots 10 --calib-shots 0 --width 1500 --height 1000 --no-progress", &out), 0) << out;
      fs::copy(session, *reference_ / material, fs::copy_options::recursive);
      std::string options = kProcessOptions;
      options.replace(options.find("{session}"), 9, (*reference_ / material).string());
      ASSERT_EQ(testing::RunMesocap("process " + (*reference_ / material).string() + " " + options + " --no-progress", &out), 0)
          << out;
    }
  }
  static void TearDownTestSuite() { delete rendered_, delete reference_; }

  // A fresh copy of the rendered sessions.
  static fs::path FreshSessions(const std::string& name) {
    const fs::path root = testing::MakeTempDir() / name;
    fs::copy(*rendered_, root, fs::copy_options::recursive);
    return root;
  }

  // The workflow's command on `root` (run in a work folder beside it, where Snakemake keeps its
  // own records).
  static std::string SnakemakeCommand(const fs::path& root, int shards, const std::string& extra = "") {
    const char* source = std::getenv("MESOCAP_SOURCE_DIR");
    const fs::path work = root.parent_path() / (root.filename().string() + "_work");
    fs::create_directories(work);
    return "cd " + work.string() + " && snakemake -s " + (fs::path(source ? source : ".") / "workflow" / "Snakefile").string() +
           " --cores 2 --keep-going --config sessions=" + root.string() + " mesocap=" + testing::MesocapBinary() +
           " shards=" + std::to_string(shards) + " " + Quoted(std::string("process_options=") + kProcessOptions) + " " +
           extra + " 2>&1";
  }

  static fs::path* rendered_;
  static fs::path* reference_;
};
fs::path* WorkflowTest::rendered_ = nullptr;
fs::path* WorkflowTest::reference_ = nullptr;

Json WithoutTimings(Json index) {
  for (auto it = index.begin(); it != index.end();)
    it = it.key().rfind("seconds", 0) == 0 || it.key() == "ms_per_slice" || it.key() == "provenance" ? index.erase(it) : ++it;
  return index;
}

bool SameFile(const fs::path& a, const fs::path& b) {
  auto x = ReadTextFile(a), y = ReadTextFile(b);
  return x.ok() && y.ok() && *x == *y;
}

// Every slice an index lists, pixel for pixel, and the index itself (timings and provenance aside).
void ExpectSameSlices(const fs::path& expected_index, const fs::path& actual_index) {
  auto a = ReadJsonFile(expected_index), b = ReadJsonFile(actual_index);
  ASSERT_TRUE(a.ok() && b.ok()) << actual_index;
  EXPECT_EQ(WithoutTimings(*a), WithoutTimings(*b)) << actual_index;
  for (const Json& entry : (*a)["slices"]) {
    const std::string file = entry["file"].get<std::string>();
    auto x = ReadImage(expected_index.parent_path() / file), y = ReadImage(actual_index.parent_path() / file);
    ASSERT_TRUE(x.ok() && y.ok()) << file;
    ASSERT_EQ(x->size(), y->size()) << file;
    EXPECT_EQ(std::memcmp(x->data(), y->data(), x->size() * sizeof(float)), 0) << actual_index << ": " << file;
  }
}

void ExpectSameOutputs(const fs::path& expected, const fs::path& actual) {
  int ptms = 0;
  for (const auto& entry : fs::directory_iterator(expected / "ptm"))
    if (entry.path().extension() == ".ptm") {
      EXPECT_TRUE(SameFile(entry.path(), actual / "ptm" / entry.path().filename())) << entry.path().filename();
      ++ptms;
    }
  EXPECT_GT(ptms, 0);
  ExpectSameSlices(expected / "slices" / "index.json", actual / "slices" / "index.json");
  ExpectSameSlices(expected / "btf" / "index.json", actual / "btf" / "index.json");
  for (const char* texture : {"base_color.png", "metallic_roughness.png", "normal.png"})
    EXPECT_TRUE(SameFile(expected / "export" / "gltf" / texture, actual / "export" / "gltf" / texture)) << texture;
  EXPECT_TRUE(fs::exists(actual / "report.html"));
}

// The stages' statuses in a job's outcome (its marker).
std::vector<std::string> Statuses(const fs::path& marker) {
  std::vector<std::string> statuses;
  auto outcome = ReadJsonFile(marker);
  if (outcome.ok())
    for (const Json& stage : outcome->value("stages", Json::array())) statuses.push_back(stage.value("status", ""));
  return statuses;
}

TEST_F(WorkflowTest, ThreeSessionsWithShardsEqualProcessOnEachAlone) {
  const fs::path root = FreshSessions("sharded");
  std::string out;
  ASSERT_EQ(testing::RunCommand(SnakemakeCommand(root, 3), &out), 0) << out;
  for (const char* session : kSessions) {
    ExpectSameOutputs(*reference_ / session, root / session);
    // The closing whole `process` run found every stage current.
    const std::vector<std::string> statuses = Statuses(root / session / "workflow" / "report.done");
    EXPECT_EQ(statuses.size(), 5u) << session;
    for (const std::string& status : statuses) EXPECT_EQ(status, "skipped (unchanged)") << session;
    // calibrate, resample, fit-ptm, 3 reconstruct shards and their merge, 3 GGX fit shards and the export.
    EXPECT_NE(out.find(session + std::string(24 - std::strlen(session), ' ') + "   11"), std::string::npos)
        << "the summary table: 11 jobs ran for " << session << "\n" << out;
  }
  // A second run: nothing to do.
  ASSERT_EQ(testing::RunCommand(SnakemakeCommand(root, 3), &out), 0) << out;
  EXPECT_NE(out.find("Nothing to be done"), std::string::npos) << out;
}

TEST_F(WorkflowTest, ABrokenSessionFailsWithItsReasonAndTheOthersComplete) {
  const fs::path root = FreshSessions("broken");
  // Its shots' journal names shots that are not there.
  fs::remove_all(root / "stones" / "shots");
  fs::create_directories(root / "stones" / "shots");
  std::string out;
  EXPECT_NE(testing::RunCommand(SnakemakeCommand(root, 1), &out), 0) << out;
  for (const char* session : {"weave", "corduroy"}) ExpectSameOutputs(*reference_ / session, root / session);
  EXPECT_FALSE(fs::exists(root / "stones" / "workflow" / "calibrate.done"));
  const size_t row = out.find("\nstones ");
  ASSERT_NE(row, std::string::npos) << out;
  const std::string line = out.substr(row + 1, out.find('\n', row + 1) - row - 1);
  EXPECT_NE(line.find("calibrate: "), std::string::npos) << line;
  EXPECT_NE(line.find("no flash shot could be read"), std::string::npos) << "says why: " << line;
}

TEST_F(WorkflowTest, AfterKillNineARerunCompletesWithoutRedoingFinishedStages) {
  const fs::path root = FreshSessions("killed");
  const fs::path pid_file = root.parent_path() / "snakemake.pid";
  ASSERT_EQ(testing::RunCommand("(" + SnakemakeCommand(root, 3) + " > " + (root.parent_path() / "first.log").string() +
                                ") & echo $! > " + pid_file.string()), 0);
  // Wait for a reconstruct shard to be done somewhere and stages to be running, then kill -9
  // Snakemake and every stage it started.
  bool killed = false;
  for (int tick = 0; tick < 1200 && !killed; ++tick) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    bool shard_done = false;
    for (const char* session : kSessions) shard_done |= fs::exists(root / session / "workflow" / "reconstruct_shard_1_of_3.done");
    std::string running;
    testing::RunCommand("pgrep -f 'mesocap process " + root.string() + "/'", &running);
    if (!shard_done || running.empty()) continue;
    testing::RunCommand("pkill -9 -f -- 'sessions=" + root.string() + " '; pkill -9 -f 'process " + root.string() + "/'");
    killed = true;
  }
  ASSERT_TRUE(killed) << "the workflow ended before a kill could land";
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  // What was finished before the kill: each stage's record in the session's cache.
  std::map<std::string, std::string> finished;
  for (const char* session : kSessions) {
    auto stages = ReadJsonFile(root / session / "stages.json");
    if (!stages.ok()) continue;
    for (const auto& [stage, record] : (*stages)["stages"].items())
      finished[std::string(session) + "/" + stage] = record.value("finished_utc", "");
  }
  ASSERT_FALSE(finished.empty());
  std::string out;
  ASSERT_EQ(testing::RunCommand(SnakemakeCommand(root, 3, "--unlock"), &out), 0) << out;
  ASSERT_EQ(testing::RunCommand(SnakemakeCommand(root, 3, "--rerun-incomplete"), &out), 0) << out;
  for (const char* session : kSessions) {
    ExpectSameOutputs(*reference_ / session, root / session);
    auto stages = ReadJsonFile(root / session / "stages.json");
    ASSERT_TRUE(stages.ok());
    for (const auto& [key, when] : finished) {
      if (key.rfind(std::string(session) + "/", 0) != 0) continue;
      EXPECT_EQ((*stages)["stages"][key.substr(key.find('/') + 1)].value("finished_utc", ""), when) << key << " was redone";
    }
  }
}

}  // namespace
}  // namespace mesocap
