#pragma once

#include <cstddef>

namespace stepstone::kb::detail {

/// Starts loading `bytes` bytes from `data` into the cache, a line at a time.
inline void prefetch(const void* data, std::size_t bytes) {
    for (std::size_t line = 0; line < bytes; line += 64) __builtin_prefetch(static_cast<const char*>(data) + line);
}

}  // namespace stepstone::kb::detail
