// Kernels compiled twice, for AVX2 + FMA (x86-64-v3) and for baseline x86-64, the clone picked at
// load time by the CPU: GCC/Clang vector extensions then become 8-wide (4-wide doubles) where the
// CPU has AVX2. Pass vector-extension values between helpers by reference only: a value returned
// from a baseline helper into an x86-64-v3 clone would change the ABI.
#pragma once

#if defined(__x86_64__) && defined(__has_attribute)
#if __has_attribute(target_clones)
#define MESOCAP_SIMD_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#endif
#endif
#ifndef MESOCAP_SIMD_CLONES
#define MESOCAP_SIMD_CLONES
#endif

// Arithmetic that must round exactly as written (each product, then each sum), in every clone:
// GCC would otherwise fuse a * b + c into one FMA in the AVX2 clone only, and results would
// depend on the CPU. (Clang fuses only within one expression: write products and sums as
// separate statements.)
#if defined(__GNUC__) && !defined(__clang__)
#define MESOCAP_NO_FP_CONTRACT __attribute__((optimize("fp-contract=off")))
#else
#define MESOCAP_NO_FP_CONTRACT
#endif
