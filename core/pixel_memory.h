// Memory for pixels. Large blocks (whole photos: tens of MB) are kept for reuse when freed, up to
// a bound: a fresh block costs the kernel a page fault per 4 KiB page on first touch, and on the
// virtual machines we run on those faults took 45% of calibrate's CPU time (perf, 24-shot demo
// session). glibc cannot keep them itself: blocks over 32 MiB are always mmap'ed and unmapped.
// (Asking Linux for transparent huge pages also saved page faults but, with the usual
// defrag=madvise, stalled the allocating thread in memory compaction for up to 0.3 s when other
// programs had fragmented memory: measured on fit-ptm.)
#pragma once

#include <cstddef>

namespace mesocap {

// Never null (throws std::bad_alloc). Blocks of at least kReusedPixelBlockBytes come from the
// cache when one of their size (up to 1/8 larger) was freed before.
void* AllocatePixelMemory(size_t bytes);
void FreePixelMemory(void* p);

inline constexpr size_t kReusedPixelBlockBytes = size_t(4) << 20;
inline constexpr size_t kPixelCacheBytes = size_t(512) << 20;  // freed blocks held, at most

// Bytes of freed blocks held for reuse now; whether the cache is on (it is off under
// AddressSanitizer, which must see every free to catch use after free).
size_t CachedPixelBytes();
bool PixelCacheEnabled();
void ReleaseCachedPixelMemory();

// The same for the libraries' own buffers (AprilTag's per-image union-find, JPEG decoding,
// OpenCV's): glibc serves allocations up to kHeapServedBytes from its heap instead of mapping each
// afresh, and keeps up to kHeapKeptBytes of freed heap before giving it back. The calibrate stage
// of the demo session: 13.0 -> 8.4 s wall, sys 6.7 -> 2.4 s; peak memory +7%. Call once, before
// the work allocates (the commands module does, as a command starts).
inline constexpr size_t kHeapServedBytes = size_t(128) << 20;
inline constexpr size_t kHeapKeptBytes = size_t(512) << 20;
void KeepLargeLibraryBuffersInHeap();

}  // namespace mesocap
