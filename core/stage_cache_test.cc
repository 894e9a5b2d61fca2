#include "core/stage_cache.h"

#include <unistd.h>

#include <gtest/gtest.h>

#include <fstream>

#include "core/atomic_file.h"
#include "core/content_hash.h"
#include "core/session_layout.h"
#include "core/provenance.h"
#include "tests/testing.h"

namespace mesocap {
namespace {

namespace fs = std::filesystem;

void WriteText(const fs::path& file, const std::string& text) {
  fs::create_directories(file.parent_path());
  std::ofstream(file, std::ios::binary) << text;
}

TEST(ContentHash, PartsAreFramedSoBoundariesCount) {
  ContentHasher ab_c, a_bc;
  ab_c.Add("ab");
  ab_c.Add("c");
  a_bc.Add("a");
  a_bc.Add("bc");
  EXPECT_NE(ab_c.Hex(), a_bc.Hex());
  EXPECT_EQ(HashBytes("same"), HashBytes("same"));
  EXPECT_EQ(HashBytes("x").size(), 32u);
}

TEST(ContentHash, AFolderHashChangesWithAnyFileNameOrContent) {
  const fs::path dir = testing::MakeTempDir() / "f";
  WriteText(dir / "a.txt", "alpha");
  WriteText(dir / "sub" / "b.txt", "beta");
  const std::string base = *HashPath(dir);
  EXPECT_EQ(*HashPath(dir), base) << "deterministic";

  WriteText(dir / "sub" / "b.txt", "betA");
  const std::string edited = *HashPath(dir);
  EXPECT_NE(edited, base);
  WriteText(dir / "sub" / "b.txt", "beta");
  EXPECT_EQ(*HashPath(dir), base) << "restoring the content restores the hash";

  fs::rename(dir / "a.txt", dir / "c.txt");
  EXPECT_NE(*HashPath(dir), base) << "a rename changes it";
  fs::rename(dir / "c.txt", dir / "a.txt");
  WriteText(dir / ".hidden", "");
  EXPECT_NE(*HashPath(dir), base) << "an added (even empty, hidden) file changes it";
  fs::remove(dir / ".hidden");
  EXPECT_EQ(*HashPath(dir), base);

  EXPECT_EQ(*HashPath(dir / "a.txt"), *HashFile(dir / "a.txt"));
  auto missing = HashPath(dir / "nope");
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.status().message().find("nope"), std::string::npos);
}

TEST(StageCache, SaysWhyAStageMustRunAndSkipsOnlyWhenNothingChanged) {
  const fs::path session = testing::MakeTempDir();
  WriteText(session / "out" / "result.txt", "first");
  auto cache = StageCache::Open(session);
  ASSERT_TRUE(cache.ok()) << cache.status().message();
  EXPECT_EQ(cache->WhyRun("fit", "h1"), "never run");

  StageRecord record;
  record.inputs_hash = "h1";
  record.outputs = {"out"};
  record.finished_utc = "2026-12-02T00:00:00Z";
  record.summary = {{"brief", "one result"}};
  ASSERT_TRUE(cache->Record("fit", record).ok());
  EXPECT_EQ(cache->WhyRun("fit", "h1"), "");
  EXPECT_NE(cache->WhyRun("fit", "h2"), "") << "changed inputs";

  // The record survives a new process: reopened from stages.json.
  auto reopened = StageCache::Open(session);
  ASSERT_TRUE(reopened.ok());
  EXPECT_EQ(reopened->WhyRun("fit", "h1"), "");
  EXPECT_EQ(*reopened->OutputsHash("fit"), *HashOutputs(session, {"out"}));
  EXPECT_EQ(reopened->Find("fit")->summary["brief"], "one result");
  EXPECT_FALSE(reopened->OutputsHash("other").ok());

  WriteText(session / "out" / "result.txt", "edited");
  EXPECT_EQ(reopened->WhyRun("fit", "h1"), "its outputs were changed since it ran");
  fs::remove_all(session / "out");
  EXPECT_EQ(reopened->WhyRun("fit", "h1"), "its output out is missing");
}

TEST(StageCache, ACorruptFileIsNamedNotIgnored) {
  const fs::path session = testing::MakeTempDir();
  for (const std::string text : {"{", "[]", R"({"format": "mesocap-stages", "stages": {"fit": {"inputs_hash": 3}}})",
                                 R"({"format": "mesocap-stages", "stages": {"fit": {"inputs_hash": "a", "outputs_hash": "b",
                                     "outputs": ["../escape"], "seconds": 1, "finished_utc": "t"}}})"}) {
    ASSERT_TRUE(WriteTextAtomically(SessionLayout(session).stage_cache(), text).ok());
    auto cache = StageCache::Open(session);
    ASSERT_FALSE(cache.ok()) << text;
    EXPECT_NE(cache.status().message().find("stages.json"), std::string::npos) << cache.status().message();
  }
}

TEST(StagingFolder, RemovesWhatAKilledRunLeftButNotALiveRunsFolder) {
  const fs::path dir = testing::MakeTempDir();
  const std::string here = "@" + HostName();
  const fs::path dead = dir / (".btf.partial-999999999" + here), live = dir / (".btf.partial-1" + here);
  const fs::path old_style = dir / ".btf.partial-999999999", remote = dir / ".btf.old-999999999@elsewhere";
  const fs::path other = dir / ".btfx.partial-999999999";
  for (const fs::path& p : {dead, live, old_style, remote, other}) fs::create_directories(p);
  auto staging = StagingFolder::Begin(dir / "btf");
  ASSERT_TRUE(staging.ok());
  EXPECT_EQ(staging->path().filename().string(), ".btf.partial-" + std::to_string(::getpid()) + here);
  EXPECT_FALSE(fs::exists(dead)) << "no process 999999999 here: left by a killed run";
  EXPECT_FALSE(fs::exists(old_style)) << "an older version's name, from this host";
  EXPECT_TRUE(fs::exists(live)) << "process 1 is alive";
  EXPECT_TRUE(fs::exists(remote)) << "a run on another host sharing the folder";
  EXPECT_TRUE(fs::exists(other)) << "another output's folder";
}

}  // namespace
}  // namespace mesocap
