#pragma once

#include <bit>
#include <cstdint>
#include <cstring>

namespace stepstone::nn {

namespace detail {
// the integers of a float's bits: one int32 for a float, a vector of them for
// a vector of floats (GCC/Clang vector extension)
template <class T>
struct FloatBits {
    typedef std::int32_t type __attribute__((vector_size(sizeof(T))));
};
template <>
struct FloatBits<float> {
    using type = std::int32_t;
};
template <class From, class To>
[[gnu::always_inline]] inline void copy_bits(const From& from, To& to) {
    static_assert(sizeof(From) == sizeof(To));
    std::memcpy(&to, &from, sizeof to);
}
}  // namespace detail

/// x = fast_exp(x) on a float or on each lane of a vector of floats (GCC/Clang
/// vector extension): every lane does the scalar's IEEE operations in its
/// order, so a lane's result is fast_exp's bit for bit. In place, so that no
/// vector crosses a call by value (whose ABI differs with and without AVX).
template <class T>
[[gnu::always_inline]] inline void fast_exp_lanes(T& x) {
    using Bits = typename detail::FloatBits<T>::type;
    const T lo = T{} - 87.0f;
    const T hi = T{} + 88.0f;
    x = x < lo ? lo : x;
    x = x > hi ? hi : x;
    // n = round(x / ln2) by the 1.5 * 2^23 trick, valid for |n| < 2^22
    constexpr float kShifter = 12582912.0f;
    const T shifted = x * 1.44269504088896341f + kShifter;
    const T n = shifted - kShifter;
    Bits exponent;
    detail::copy_bits(shifted, exponent);
    exponent -= std::bit_cast<std::int32_t>(kShifter);
    // r = x - n ln2 with ln2 split in a short and a long part
    T r = x - n * 0.693359375f;
    r = r + n * 2.12194440e-4f;
    T p = T{} + 1.9875691500e-4f;
    p = p * r + 1.3981999507e-3f;
    p = p * r + 8.3334519073e-3f;
    p = p * r + 4.1665795894e-2f;
    p = p * r + 1.6666665459e-1f;
    p = p * r + 5.0000001201e-1f;
    const T e = p * (r * r) + r + 1.0f;
    // multiply by 2^n through the exponent field
    Bits bits;
    detail::copy_bits(e, bits);
    bits += exponent * (1 << 23);
    detail::copy_bits(bits, x);
}

/// exp(x) in float without a library call, so loops over neurons vectorise.
/// Cody-Waite range reduction x = n ln2 + r and Cephes' degree-6 polynomial
/// for exp(r); x is clamped to [-87, 88], so the result is always a normal
/// float. Relative error below 3e-7 (tested against std::exp in double).
/// Branch-free and bit-identical wherever IEEE float arithmetic is used
/// without contraction (the project builds with -ffp-contract=off).
inline float fast_exp(float x) {
    fast_exp_lanes(x);
    return x;
}

/// sum = sigmoid(scaled_bias, sum) on a float or on each lane of a vector of
/// floats, bit for bit the scalar's in every lane.
template <class T>
[[gnu::always_inline]] inline void sigmoid_lanes(const T& scaled_bias, T& sum) {
    T e = scaled_bias - sum;
    fast_exp_lanes(e);
    sum = 1.0f / (1.0f + e);
}

/// nn2's AfSigmoidBias (docs/original.md: network) with the bias already scaled:
/// 1 / (1 + exp(scaled_bias - sum)) where scaled_bias = bias_scale * b.
inline float sigmoid(float scaled_bias, float sum) {
    sigmoid_lanes(scaled_bias, sum);
    return sum;
}

}  // namespace stepstone::nn
