#pragma once

#include <charconv>
#include <string>

namespace stepstone::kb::detail {

/// The shortest text that reads back as `value` (1.83, not 1.8300000000000001).
inline std::string number(double value) {
    char buffer[32];
    const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
    return std::string(buffer, result.ptr);
}

}  // namespace stepstone::kb::detail
