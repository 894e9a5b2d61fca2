#include "core/atomic_file.h"

#include <gtest/gtest.h>

#include <fstream>

#include "core/provenance.h"
#include "tests/testing.h"

namespace mesocap {
namespace {

TEST(AtomicFile, WritesAndReplacesWithoutLeavingTemps) {
  const auto dir = testing::MakeTempDir();
  const auto path = dir / "a.txt";
  ASSERT_TRUE(WriteTextAtomically(path, "first").ok());
  ASSERT_TRUE(WriteTextAtomically(path, "second").ok());
  EXPECT_EQ(*ReadTextFile(path), "second");
  int files = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir)) ++files;
  EXPECT_EQ(files, 1);
}

TEST(AtomicFile, FailedWriterLeavesTargetUntouched) {
  const auto dir = testing::MakeTempDir();
  const auto path = dir / "a.txt";
  ASSERT_TRUE(WriteTextAtomically(path, "keep").ok());
  const Status st = WriteFileAtomically(path, [](const std::filesystem::path& temp) {
    std::FILE* f = std::fopen(temp.c_str(), "w");
    std::fputs("half", f);
    std::fclose(f);
    return Status::Error("simulated failure");
  });
  EXPECT_FALSE(st.ok());
  EXPECT_EQ(*ReadTextFile(path), "keep");
  int files = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir)) ++files;
  EXPECT_EQ(files, 1);
}

TEST(AtomicFile, FullDiskGivesAnErrorNamingTheFile) {
  if (!std::filesystem::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  const Status st = AppendLineDurably("/dev/full", "x");
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.message().find("/dev/full"), std::string::npos);
}

TEST(AtomicFile, AWriteRemovesTheTempsOfEndedRunsAndKeepsLiveOnes) {
  const auto dir = testing::MakeTempDir();
  // What runs killed mid-write leave: a temp and a file set member's nested temp (pid 999999999
  // cannot exist: pid_max is at most 2^22), next to a live run's temp and a user's hidden file.
  // Names carry PID@HOST (older versions wrote the PID alone); another host's run is never judged.
  const std::string here = "@" + HostName();
  const std::vector<std::string> stale = {".a.tmp999999999_0.txt", "..b.tmp999999999_0.tmp999999999_1.ptm",
                                          ".d.tmp999999999" + here + "_0.txt"};
  const std::vector<std::string> kept = {".c.tmp1_0.txt", ".notes.tmp", ".x.tmpfile_1.txt", ".e.tmp999999999@elsewhere_0.txt",
                                         ".f.tmp1" + here + "_0.txt"};
  for (const auto& name : stale) ASSERT_TRUE(WriteTextAtomically(dir / name, "left").ok());
  for (const auto& name : kept) ASSERT_TRUE(WriteTextAtomically(dir / name, "keep").ok());
  // The sweep runs once per folder and process: a fresh subfolder sees this write's sweep.
  const auto sub = dir / "sub";
  std::filesystem::create_directory(sub);
  for (const auto& name : stale) std::filesystem::rename(dir / name, sub / name);
  for (const auto& name : kept) std::filesystem::rename(dir / name, sub / name);
  ASSERT_TRUE(WriteTextAtomically(sub / "a.txt", "new").ok());
  for (const auto& name : stale) EXPECT_FALSE(std::filesystem::exists(sub / name)) << name;
  for (const auto& name : kept) EXPECT_TRUE(std::filesystem::exists(sub / name)) << name;
  EXPECT_EQ(*ReadTextFile(sub / "a.txt"), "new");
}

int FilesIn(const std::filesystem::path& dir) {
  int files = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir)) ++files;
  return files;
}

// A rename that fails after others succeeded (the second file's folder vanished between Stage and
// Commit): the first file is put back, the third never moved; nothing else is left.
TEST(OutputFileSet, AFailureBetweenTheRenamesPutsTheEarlierFilesBack) {
  const auto dir = testing::MakeTempDir();
  ASSERT_TRUE(WriteTextAtomically(dir / "a.txt", "old a").ok());
  ASSERT_TRUE(WriteTextAtomically(dir / "c.txt", "old c").ok());
  std::filesystem::create_directory(dir / "sub");
  {
    OutputFileSet outputs;
    for (const char* name : {"a.txt", "sub/b.txt", "c.txt"})
      ASSERT_TRUE(outputs.Stage(dir / name, [](const auto& temp) { return WriteTextAtomically(temp, "new"); }).ok());
    std::filesystem::remove_all(dir / "sub");
    const Status st = outputs.Commit();
    ASSERT_FALSE(st.ok());
    EXPECT_NE(st.message().find("b.txt"), std::string::npos) << st.message();
  }
  EXPECT_EQ(*ReadTextFile(dir / "a.txt"), "old a");
  EXPECT_EQ(*ReadTextFile(dir / "c.txt"), "old c");
  EXPECT_EQ(FilesIn(dir), 2);
}

// What a run killed between its renames leaves: a backup whose new file never arrived is put back
// by the next write into the folder; one whose new file is in place is removed.
TEST(OutputFileSet, AKilledCommitsBackupsArePutBackOrRemoved) {
  const auto dir = testing::MakeTempDir();
  const std::string dead = ".old-999999999@" + HostName();  // pid 999999999 cannot exist
  const auto write = [&](const std::string& name, const std::string& text) { std::ofstream(dir / name) << text; };
  write(".report.json" + dead, "old report");  // its new file never arrived
  write(".material.ptm" + dead, "old ptm");    // its new file is in place
  write("material.ptm", "new ptm");
  ASSERT_TRUE(WriteTextAtomically(dir / "other.txt", "x").ok());  // the first write into the folder sweeps it
  EXPECT_EQ(*ReadTextFile(dir / "report.json"), "old report");
  EXPECT_EQ(*ReadTextFile(dir / "material.ptm"), "new ptm");
  EXPECT_EQ(FilesIn(dir), 3);
}

TEST(OutputFileSet, AFailureLeavesEveryOldFileAndNoTemps) {
  const auto dir = testing::MakeTempDir();
  ASSERT_TRUE(WriteTextAtomically(dir / "a.txt", "old a").ok());
  {
    OutputFileSet outputs;
    ASSERT_TRUE(outputs.Stage(dir / "a.txt", [](const auto& temp) { return WriteTextAtomically(temp, "new a"); }).ok());
    const Status st = outputs.Stage(dir / "b.txt", [](const auto& temp) {
      return Status::Error(temp.string() + ": disk full");
    });
    ASSERT_FALSE(st.ok());
    EXPECT_EQ(st.message(), (dir / "b.txt").string() + ": disk full") << "the error names the final file";
  }
  EXPECT_EQ(*ReadTextFile(dir / "a.txt"), "old a");
  EXPECT_EQ(FilesIn(dir), 1);
}

TEST(OutputFileSet, CommitPutsEveryFileInPlace) {
  const auto dir = testing::MakeTempDir();
  ASSERT_TRUE(WriteTextAtomically(dir / "a.txt", "old a").ok());
  OutputFileSet outputs;
  ASSERT_TRUE(outputs.Stage(dir / "a.txt", [](const auto& temp) { return WriteTextAtomically(temp, "new a"); }).ok());
  ASSERT_TRUE(outputs.Stage(dir / "b.txt", [](const auto& temp) { return WriteTextAtomically(temp, "new b"); }).ok());
  EXPECT_EQ(*ReadTextFile(dir / "a.txt"), "old a") << "nothing moves before Commit";
  ASSERT_TRUE(outputs.Commit().ok());
  EXPECT_EQ(*ReadTextFile(dir / "a.txt"), "new a");
  EXPECT_EQ(*ReadTextFile(dir / "b.txt"), "new b");
  EXPECT_EQ(FilesIn(dir), 2);
}

}  // namespace
}  // namespace mesocap
