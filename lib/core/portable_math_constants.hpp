#pragma once

#include <array>
#include <cstddef>

// The constants and the arithmetic of portable::sincos, shared by its scalar and lane builds
// (core/portable_math.cpp, core/portable_math_lanes.cpp) so that they cannot drift apart.
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

// The arithmetic below is written once for a double and for each lane of a vector of doubles
// (GCC's vector extension, which the intrinsics' __m256d and __m512d are): every lane does the
// scalar's IEEE operations in its order, and the project builds without contraction into FMA,
// so every build gives the scalar's bits. Inline, and results through references, so that no
// vector crosses a call by value (whose ABI differs with and without AVX).

// p = c[0] + z c[1] + ... + z^7 c[7], by Horner from the highest term
template <class T>
[[gnu::always_inline]] inline void horner(const T& z, const std::array<double, 8>& c, T& p) {
    p = T{} + c[7];  // c[7] in every lane (0 + c[7] is c[7]: it is not 0)
    for (std::size_t k = 7; k-- > 0;) p = c[k] + z * p;
}

// r = x - k pi/2 with pi/2 in three parts, k the nearest integer to x 2/pi
template <class T>
[[gnu::always_inline]] inline void reduce(const T& x, const T& k, T& r) {
    r = ((x - k * kHalfPi1) - k * kHalfPi2) - k * kHalfPi3;
}

// s = sin r and c = cos r, |r| <= pi/4 (plus rounding): Taylor series to r^17 and r^18, whose
// first omitted terms are below 1e-19
template <class T>
[[gnu::always_inline]] inline void sincos_kernel(const T& r, T& s, T& c) {
    const T z = r * r;
    T p;
    horner(z, kSinCoefficients, p);
    s = r + r * (z * p);
    // cos: the series from z^2 on, with its signs flipped: cos r = 1 - (z/2 + z^2 p), the small
    // terms summed first
    horner(z, kCosCoefficients, p);
    const T half = 0.5 * z;
    c = 1.0 - (half + z * (z * p));
}

}  // namespace stepstone::portable::detail
