#pragma once

#include <bit>
#include <cmath>
#include <cstdint>

namespace stepstone::sim {

/// cos and sin of an angle, as std::cos and std::sin give them.
struct CosSin {
    double c = 1.0;
    double s = 0.0;
};

/// std::cos and std::sin of the last angle asked, compared bit for bit;
/// starts with those of +0.
struct CosSinMemo {
    std::uint64_t bits = 0;
    CosSin value;

    CosSin get(double angle) {
        const auto angle_bits = std::bit_cast<std::uint64_t>(angle);
        if (bits != angle_bits) {
            value = {std::cos(angle), std::sin(angle)};
            bits = angle_bits;
        }
        return value;
    }
};

namespace detail {
inline thread_local CosSinMemo heading_memo;
}  // namespace detail

/// std::cos and std::sin of `angle`, remembering the last angle asked on the
/// calling thread: the odometry of a straight move and the sensors at the
/// pose it reaches ask for the same heading. The memo holds the exact values
/// (the angle is compared bit for bit), so results never depend on it, and
/// each thread has its own.
inline CosSin cos_sin(double angle) { return detail::heading_memo.get(angle); }

}  // namespace stepstone::sim
