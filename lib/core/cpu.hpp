#pragma once

#include <cstdlib>

namespace stepstone {

/// False when the environment sets STEPSTONE_NO_AVX2 (to any value): the
/// simulator, the networks, the diversity and the knowledge base then run the
/// generic builds of their kernels, as on a CPU without AVX2. Every kernel
/// gives the same bits in either build, and the tests check it end to end by
/// running a machine without AVX2 this way. Read once, at the first call.
inline bool avx2_allowed() {
    static const bool allowed = std::getenv("STEPSTONE_NO_AVX2") == nullptr;
    return allowed;
}

}  // namespace stepstone
