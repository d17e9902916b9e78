#pragma once

// Kernels of the knowledge base built twice, generic and AVX2, the copy
// picked when the program loads (GCC's target_clones). Both copies compile
// the same source under -ffp-contract=off, so they give the same bits.
#if defined(__GNUC__) && !defined(__clang__) && (defined(__x86_64__) || defined(__i386__)) && defined(__linux__)
#define STEPSTONE_KB_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define STEPSTONE_KB_CLONES
#endif
