#pragma once

#include <cstdlib>

namespace stepstone {

/// True when the hand-written AVX2 kernels of the simulator, the networks, the
/// diversity and the knowledge base may run: an x86 CPU with AVX2, and the
/// environment does not set STEPSTONE_NO_AVX2 (to any value). Without either,
/// every module runs the generic builds of its kernels, as on a CPU without
/// AVX2. Every kernel gives the same bits in either build, and the tests check
/// it end to end by running a machine without AVX2 this way. Read once.
inline bool avx2_kernels_allowed() {
#if defined(__x86_64__) || defined(__i386__)
    static const bool allowed = [] {
        __builtin_cpu_init();
        return __builtin_cpu_supports("avx2") && std::getenv("STEPSTONE_NO_AVX2") == nullptr;
    }();
    return allowed;
#else
    return false;
#endif
}

/// True when the AVX-512 builds of the kernels that have one (the lanes' sine
/// and cosine, the networks' sigmoids in lanes) may run instead of their AVX2
/// builds: avx2_kernels_allowed(), a CPU with AVX-512 F, VL and DQ, and the
/// environment does not set STEPSTONE_NO_AVX512. Each gives its AVX2 build's
/// bits: IEEE operations lane by lane, twice as many lanes a vector. Read once.
inline bool avx512_kernels_allowed() {
#if defined(__x86_64__) || defined(__i386__)
    static const bool allowed = [] {
        return avx2_kernels_allowed() && __builtin_cpu_supports("avx512f") &&
               __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512dq") &&
               std::getenv("STEPSTONE_NO_AVX512") == nullptr;
    }();
    return allowed;
#else
    return false;
#endif
}

}  // namespace stepstone
