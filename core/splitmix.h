// SplitMix64 (Steele, Lea & Flood): a cheap, well-mixed 64-bit hash. Hashing (seed, index) gives
// a counter-based random stream whose draws do not depend on the order they are made in, so
// parallel work stays reproducible for any thread count.
#pragma once

#include <cstdint>

namespace mesocap {

inline uint64_t SplitMix64(uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

}  // namespace mesocap
