#pragma once

// Helpers of the simulator's lane kernels (robot.cpp, arena_lanes.cpp), which hold their
// lanes in GCC vector-extension values.

#include <cstddef>
#include <cstdint>
#include <cstring>

namespace stepstone::sim::lanes {

/// Fills `vector`'s lanes from memory. By reference, so that no vector value crosses a call
/// in the baseline (SSE2) build, where GCC would pass it through memory.
template <class Vector>
[[gnu::always_inline]] inline void load(Vector& vector, const void* from) {
    std::memcpy(&vector, from, sizeof vector);
}

/// N lanes of doubles, of the floats they convert to and from, and of 64-bit masks: one SSE
/// register of doubles for N = 2, one AVX register for N = 4 (one specialisation a width:
/// GCC drops a vector_size that depends on a template argument).
template <std::size_t N>
struct DoubleVectors;
template <>
struct DoubleVectors<2> {
    using Doubles = double __attribute__((vector_size(16)));
    using Floats = float __attribute__((vector_size(8)));
    using Longs = std::int64_t __attribute__((vector_size(16)));
};
template <>
struct DoubleVectors<4> {
    using Doubles = double __attribute__((vector_size(32)));
    using Floats = float __attribute__((vector_size(16)));
    using Longs = std::int64_t __attribute__((vector_size(32)));
};

}  // namespace stepstone::sim::lanes
