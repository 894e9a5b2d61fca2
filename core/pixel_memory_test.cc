#include "core/pixel_memory.h"

#include <sys/resource.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <vector>

#include <gtest/gtest.h>

#include "core/image.h"

namespace mesocap {
namespace {

constexpr size_t kMiB = size_t(1) << 20;

TEST(PixelMemory, SmallAndLargeBlocksAreAlignedAndWritable) {
  for (size_t bytes : {size_t(0), size_t(1), size_t(1000), 5 * kMiB, 40 * kMiB}) {
    void* p = AllocatePixelMemory(bytes);
    ASSERT_NE(p, nullptr);
    EXPECT_EQ(reinterpret_cast<uintptr_t>(p) % 64, 0u) << bytes;
    std::memset(p, 0xab, bytes);
    FreePixelMemory(p);
  }
  FreePixelMemory(nullptr);
}

TEST(PixelMemory, AFreedLargeBlockIsReusedForTheSameSizeOnly) {
  if (!PixelCacheEnabled()) GTEST_SKIP() << "the cache is off under AddressSanitizer";
  ReleaseCachedPixelMemory();
  void* a = AllocatePixelMemory(72 * kMiB);
  FreePixelMemory(a);
  EXPECT_EQ(CachedPixelBytes(), 72 * kMiB);
  // Much smaller: not served from the 72 MiB block, which stays cached.
  void* small = AllocatePixelMemory(24 * kMiB);
  EXPECT_NE(small, a);
  EXPECT_EQ(CachedPixelBytes(), 72 * kMiB);
  // A little smaller (within 1/8): the same block again, and no longer cached.
  void* b = AllocatePixelMemory(70 * kMiB);
  EXPECT_EQ(b, a);
  EXPECT_EQ(CachedPixelBytes(), 0u);
  FreePixelMemory(b);
  FreePixelMemory(small);
  EXPECT_EQ(CachedPixelBytes(), 96 * kMiB);
  ReleaseCachedPixelMemory();
  EXPECT_EQ(CachedPixelBytes(), 0u);
}

TEST(PixelMemory, TheCacheStaysWithinItsBoundOldestBlocksFirstOut) {
  if (!PixelCacheEnabled()) GTEST_SKIP() << "the cache is off under AddressSanitizer";
  ReleaseCachedPixelMemory();
  const size_t block = 100 * kMiB;
  std::vector<void*> blocks;
  for (size_t k = 0; k < kPixelCacheBytes / block + 3; ++k) blocks.push_back(AllocatePixelMemory(block));
  for (void* p : blocks) FreePixelMemory(p);
  EXPECT_LE(CachedPixelBytes(), kPixelCacheBytes);
  EXPECT_EQ(CachedPixelBytes(), kPixelCacheBytes / block * block);
  // A block served again is one of the newest freed; the oldest were released.
  void* again = AllocatePixelMemory(block);
  const auto kept = blocks.end() - std::ptrdiff_t(kPixelCacheBytes / block);
  EXPECT_NE(std::find(kept, blocks.end(), again), blocks.end());
  FreePixelMemory(again);
  ReleaseCachedPixelMemory();
}

TEST(PixelMemory, ImagesOnReusedMemoryHoldTheirFill) {
  ReleaseCachedPixelMemory();
  {
    Image dirty(2000, 1000, 3, 7.0f);
  }
  Image clean(2000, 1000, 3);
  for (size_t i = 0; i < clean.size(); i += 997) ASSERT_EQ(clean.data()[i], 0.0f) << i;
  ReleaseCachedPixelMemory();
}

}  // namespace
}  // namespace mesocap

namespace mesocap {
namespace {

long MinorPageFaults() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_minflt;
}

// A library's 64 MB buffer, freed and asked for again: glibc would have unmapped it and every page
// would fault afresh (16384 pages); kept in the heap, the second use faults on almost none.
TEST(PixelMemory, ALargeLibraryBufferFreedAndAskedForAgainReusesItsPages) {
  if (!PixelCacheEnabled()) GTEST_SKIP() << "the sanitizer's allocator ignores glibc's settings";
  KeepLargeLibraryBuffersInHeap();
  constexpr size_t kBytes = size_t(64) << 20;
  auto touch_and_free = [&] {
    auto* p = static_cast<volatile char*>(std::malloc(kBytes));
    ASSERT_NE(p, nullptr);
    for (size_t i = 0; i < kBytes; i += 4096) p[i] = char(i);
    std::free(const_cast<char*>(p));
  };
  touch_and_free();
  const long before = MinorPageFaults();
  touch_and_free();
  EXPECT_LT(MinorPageFaults() - before, 1000);
}

}  // namespace
}  // namespace mesocap
