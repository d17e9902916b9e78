#pragma once

#include <bit>
#include <cstdint>

namespace stepstone::nn {

/// exp(x) in float without a library call, so loops over neurons vectorise.
/// Cody-Waite range reduction x = n ln2 + r and Cephes' degree-6 polynomial
/// for exp(r); x is clamped to [-87, 88], so the result is always a normal
/// float. Relative error below 3e-7 (tested against std::exp in double).
/// Branch-free and bit-identical wherever IEEE float arithmetic is used
/// without contraction (the project builds with -ffp-contract=off).
inline float fast_exp(float x) {
    x = x < -87.0f ? -87.0f : x;
    x = x > 88.0f ? 88.0f : x;
    // n = round(x / ln2) by the 1.5 * 2^23 trick, valid for |n| < 2^22
    constexpr float kShifter = 12582912.0f;
    const float shifted = x * 1.44269504088896341f + kShifter;
    const float n = shifted - kShifter;
    const std::int32_t exponent = std::bit_cast<std::int32_t>(shifted) - std::bit_cast<std::int32_t>(kShifter);
    // r = x - n ln2 with ln2 split in a short and a long part
    float r = x - n * 0.693359375f;
    r = r + n * 2.12194440e-4f;
    float p = 1.9875691500e-4f;
    p = p * r + 1.3981999507e-3f;
    p = p * r + 8.3334519073e-3f;
    p = p * r + 4.1665795894e-2f;
    p = p * r + 1.6666665459e-1f;
    p = p * r + 5.0000001201e-1f;
    const float e = p * (r * r) + r + 1.0f;
    // multiply by 2^n through the exponent field
    return std::bit_cast<float>(std::bit_cast<std::int32_t>(e) + exponent * (1 << 23));
}

/// nn2's AfSigmoidBias (docs/original.md: network) with the bias already scaled:
/// 1 / (1 + exp(scaled_bias - sum)) where scaled_bias = bias_scale * b.
inline float sigmoid(float scaled_bias, float sum) { return 1.0f / (1.0f + fast_exp(scaled_bias - sum)); }

/// The same sigmoid through std::exp in double, as nn2 computes it; used by
/// the accuracy test and the pointer-based baseline.
double sigmoid_exact(double scaled_bias, double sum);

}  // namespace stepstone::nn
