#pragma once

// Kernels of the knowledge base built twice, generic and AVX2, the copy
// picked when the program loads (GCC's target_clones). Both copies compile
// the same source under -ffp-contract=off, so they give the same bits.
#if defined(__GNUC__) && !defined(__clang__) && (defined(__x86_64__) || defined(__i386__)) && defined(__linux__)
#define STEPSTONE_KB_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define STEPSTONE_KB_CLONES
#endif

#include <cstdlib>

#include "core/cpu.hpp"

namespace stepstone::kb::detail {

/// True when the hand-written AVX2 kernels of the knowledge base run: the CPU
/// has AVX2 and the environment sets neither STEPSTONE_KB_GENERIC (so that the
/// generic kernels are tested, and can be compared, on any machine) nor
/// STEPSTONE_NO_AVX2 (core/cpu.hpp).
inline bool use_avx2() {
    static const bool avx2 = avx2_kernels_allowed() && std::getenv("STEPSTONE_KB_GENERIC") == nullptr;
    return avx2;
}

}  // namespace stepstone::kb::detail
