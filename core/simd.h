// Kernels compiled twice, for AVX2 + FMA (x86-64-v3) and for baseline x86-64, the clone picked at
// load time by the CPU: GCC/Clang vector extensions then become 8-wide (4-wide doubles) where the
// CPU has AVX2. Pass vector-extension values between helpers by reference only: a value returned
// from a baseline helper into an x86-64-v3 clone would change the ABI. A file with clones must be
// listed in CMakeLists.txt's TSan exception: gcc instruments the clones' ifunc resolver, which the
// dynamic loader runs before the TSan runtime starts.
#pragma once

#if defined(__x86_64__) && defined(__has_attribute)
#if __has_attribute(target_clones)
#define MESOCAP_SIMD_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#endif
#endif
#ifndef MESOCAP_SIMD_CLONES
#define MESOCAP_SIMD_CLONES
#endif
