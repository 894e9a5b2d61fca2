#include "core/scratch_file.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <numeric>
#include <vector>

#include "core/parallel.h"
#include "tests/testing.h"

namespace mesocap {
namespace {

namespace fs = std::filesystem;

TEST(ScratchFile, RowsWrittenInAnyOrderFromSeveralThreadsReadBack) {
  const auto dir = testing::MakeTempDir();
  auto file = ScratchFile::Create(dir);
  ASSERT_TRUE(file.ok()) << file.status().message();
  constexpr int kRows = 200, kRowFloats = 3001;
  ParallelFor(0, kRows, [&](int r) {
    const int y = kRows - 1 - r;
    std::vector<float> row(kRowFloats);
    std::iota(row.begin(), row.end(), float(y * kRowFloats));
    ASSERT_TRUE(file->Write(uint64_t(y) * sizeof row[0] * kRowFloats, row.data(), sizeof row[0] * kRowFloats).ok());
  });
  std::vector<float> row(kRowFloats);
  for (int y = 0; y < kRows; ++y) {
    ASSERT_TRUE(file->Read(uint64_t(y) * sizeof row[0] * kRowFloats, row.data(), sizeof row[0] * kRowFloats).ok());
    for (int x = 0; x < kRowFloats; x += 500) ASSERT_EQ(row[size_t(x)], float(y * kRowFloats + x));
  }
  // Nothing is left in the folder: the file has no name.
  EXPECT_TRUE(fs::is_empty(dir));
}

TEST(ScratchFile, ReadingPastWhatWasWrittenAndAMissingFolderAreErrors) {
  const auto dir = testing::MakeTempDir();
  auto file = ScratchFile::Create(dir);
  ASSERT_TRUE(file.ok());
  const char bytes[4] = {1, 2, 3, 4};
  ASSERT_TRUE(file->Write(0, bytes, sizeof bytes).ok());
  char back[8];
  const Status past = file->Read(0, back, sizeof back);
  ASSERT_FALSE(past.ok());
  EXPECT_NE(past.message().find(dir.string()), std::string::npos) << past.message();
  const auto missing = ScratchFile::Create(dir / "no-such-folder");
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.status().message().find("no-such-folder"), std::string::npos) << missing.status().message();
}

}  // namespace
}  // namespace mesocap
