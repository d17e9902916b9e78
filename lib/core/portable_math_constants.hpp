#pragma once

#include <array>
#include <cstddef>

// The constants of portable::sincos, shared by its scalar and lane builds
// (core/portable_math.cpp, core/portable_math_lanes.cpp) so the two cannot drift apart.
namespace stepstone::portable::detail {

// pi/2 in three parts: the first two of 33 significant bits, so that k * part
// is exact for |k| < 2^20
inline constexpr double kHalfPi1 = 0x1.921fb54400000p+0;
inline constexpr double kHalfPi2 = 0x1.0b4611a600000p-34;
inline constexpr double kHalfPi3 = 0x1.3198a2e037073p-69;
inline constexpr double kTwoOverPi = 0x1.45f306dc9c883p-1;

// 1 / n!, rounded once
constexpr double inverse_factorial(int n) {
    double f = 1.0;
    for (int i = 2; i <= n; ++i) f *= static_cast<double>(i);
    return 1.0 / f;
}

// The Taylor coefficients (-1)^(k+1) / (first + 2k)!, k = 0..7, each rounded once: from 1/3! for
// sin's series, from 1/4! for cos's
constexpr std::array<double, 8> alternating_coefficients(int first) {
    std::array<double, 8> c{};
    for (std::size_t k = 0; k < 8; ++k) {
        c[k] = (k % 2 == 0 ? -1.0 : 1.0) * inverse_factorial(first + 2 * static_cast<int>(k));
    }
    return c;
}
inline constexpr auto kSinCoefficients = alternating_coefficients(3);
inline constexpr auto kCosCoefficients = alternating_coefficients(4);

}  // namespace stepstone::portable::detail
