#include "core/atomic_file.h"

#include <gtest/gtest.h>

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

int FilesIn(const std::filesystem::path& dir) {
  int files = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir)) ++files;
  return files;
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
