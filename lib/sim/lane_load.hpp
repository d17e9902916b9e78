#pragma once

// A helper of the simulator's lane kernels (robot.cpp, arena_lanes.cpp), which hold their
// lanes in GCC vector-extension values.

#include <cstring>

namespace stepstone::sim::lanes {

/// Fills `vector`'s lanes from memory. By reference, so that no vector value crosses a call
/// in the baseline (SSE2) build, where GCC would pass it through memory.
template <class Vector>
[[gnu::always_inline]] inline void load(Vector& vector, const void* from) {
    std::memcpy(&vector, from, sizeof vector);
}

}  // namespace stepstone::sim::lanes
