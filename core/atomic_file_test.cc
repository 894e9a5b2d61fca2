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

}  // namespace
}  // namespace mesocap
