#include "core/pixel_memory.h"

#include <malloc.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <new>
#include <vector>

#if defined(__SANITIZE_ADDRESS__)
#define MESOCAP_NO_PIXEL_CACHE 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define MESOCAP_NO_PIXEL_CACHE 1
#endif
#endif

namespace mesocap {
namespace {

// Every block starts with a header holding its capacity; the samples follow, 64-byte aligned.
constexpr size_t kHeaderBytes = 64;

struct Block {
  size_t capacity;
  void* base;
};

struct Cache {
  std::mutex mutex;
  std::vector<Block> free_blocks;  // oldest first
  size_t bytes = 0;
};

// Never destroyed: images held by static objects may be freed after it would be.
Cache& TheCache() {
  static Cache* cache = new Cache;
  return *cache;
}

size_t CapacityOf(void* base) {
  size_t capacity;
  std::memcpy(&capacity, base, sizeof capacity);
  return capacity;
}

// A freed block of `bytes` to at most 1/8 more (the tightest), or null.
void* TakeCached(size_t bytes) {
  Cache& cache = TheCache();
  std::lock_guard lock(cache.mutex);
  auto best = cache.free_blocks.end();
  for (auto it = cache.free_blocks.begin(); it != cache.free_blocks.end(); ++it)
    if (it->capacity >= bytes && it->capacity <= bytes + bytes / 8 &&
        (best == cache.free_blocks.end() || it->capacity < best->capacity))
      best = it;
  if (best == cache.free_blocks.end()) return nullptr;
  void* base = best->base;
  cache.bytes -= best->capacity;
  cache.free_blocks.erase(best);
  return base;
}

// Keeps `base` for reuse, freeing the oldest blocks beyond the bound.
void KeepCached(void* base, size_t capacity) {
  std::vector<void*> evicted;
  {
    Cache& cache = TheCache();
    std::lock_guard lock(cache.mutex);
    cache.free_blocks.push_back({capacity, base});
    cache.bytes += capacity;
    size_t drop = 0;
    while (cache.bytes > kPixelCacheBytes) {
      cache.bytes -= cache.free_blocks[drop].capacity;
      evicted.push_back(cache.free_blocks[drop++].base);
    }
    cache.free_blocks.erase(cache.free_blocks.begin(), cache.free_blocks.begin() + drop);
  }
  for (void* p : evicted) std::free(p);  // outside the lock: unmapping takes time
}

}  // namespace

void KeepLargeLibraryBuffersInHeap() {
  mallopt(M_MMAP_THRESHOLD, int(kHeapServedBytes));
  mallopt(M_TRIM_THRESHOLD, int(kHeapKeptBytes));
}

bool PixelCacheEnabled() {
#if defined(MESOCAP_NO_PIXEL_CACHE)
  return false;
#else
  return true;
#endif
}

void* AllocatePixelMemory(size_t bytes) {
  bytes = std::max<size_t>(bytes, 1);
  void* base = nullptr;
  if (PixelCacheEnabled() && bytes >= kReusedPixelBlockBytes) base = TakeCached(bytes);
  if (!base) {
    base = std::aligned_alloc(kHeaderBytes, kHeaderBytes + (bytes + kHeaderBytes - 1) / kHeaderBytes * kHeaderBytes);
    if (!base) throw std::bad_alloc();
    std::memcpy(base, &bytes, sizeof bytes);
  }
  return static_cast<char*>(base) + kHeaderBytes;
}

void FreePixelMemory(void* p) {
  if (!p) return;
  void* base = static_cast<char*>(p) - kHeaderBytes;
  const size_t capacity = CapacityOf(base);
  if (PixelCacheEnabled() && capacity >= kReusedPixelBlockBytes && capacity <= kPixelCacheBytes)
    KeepCached(base, capacity);
  else
    std::free(base);
}

size_t CachedPixelBytes() {
  Cache& cache = TheCache();
  std::lock_guard lock(cache.mutex);
  return cache.bytes;
}

void ReleaseCachedPixelMemory() {
  std::vector<Block> blocks;
  {
    Cache& cache = TheCache();
    std::lock_guard lock(cache.mutex);
    blocks.swap(cache.free_blocks);
    cache.bytes = 0;
  }
  for (const Block& b : blocks) std::free(b.base);
}

}  // namespace mesocap
