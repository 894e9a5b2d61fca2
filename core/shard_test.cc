// Shards: every item taken once, in order, in balanced shares; only "I/N" parses.
#include "core/shard.h"

#include <gtest/gtest.h>

namespace mesocap {
namespace {

TEST(Shard, TheSharesCoverEveryItemOnceInOrderAndDifferByAtMostOne) {
  for (const size_t total : {size_t(0), size_t(1), size_t(7), size_t(289), size_t(6561)})
    for (const int count : {1, 3, 7, 8, 100}) {
      size_t next = 0, smallest = total, largest = 0;
      for (int index = 1; index <= count; ++index) {
        const auto [first, last] = Shard{index, count}.Range(total);
        EXPECT_EQ(first, next) << total << " " << index << "/" << count;
        EXPECT_LE(first, last);
        smallest = std::min(smallest, last - first), largest = std::max(largest, last - first);
        next = last;
      }
      EXPECT_EQ(next, total);
      EXPECT_LE(largest - smallest, 1u);
    }
}

TEST(Shard, OnlyIndexSlashCountParses) {
  const auto parsed = Shard::Parse("3/7");
  ASSERT_TRUE(parsed);
  EXPECT_EQ(parsed->index, 3);
  EXPECT_EQ(parsed->count, 7);
  EXPECT_EQ(parsed->Name(), "3/7");
  for (const char* bad : {"", "3", "/7", "3/", "0/7", "8/7", "-1/7", "3/7x", " 3/7", "3/ 7", "1/1000", "3.0/7", "a/b"})
    EXPECT_FALSE(Shard::Parse(bad)) << bad;
}

}  // namespace
}  // namespace mesocap
