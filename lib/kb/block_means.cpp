#include "kb/block_means.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "core/assert.hpp"
#include "kb/detail/simd.hpp"

namespace stepstone::kb {

namespace {
// four floats, four doubles (GCC and Clang vector extensions)
typedef float Floats4 __attribute__((vector_size(4 * sizeof(float))));
typedef double Quad __attribute__((vector_size(4 * sizeof(double))));
}  // namespace

BlockMeans::BlockMeans(std::size_t width, std::size_t channels, std::size_t blocks)
    : width_(width), channels_(channels), blocks_(std::clamp<std::size_t>(blocks, 1, std::max<std::size_t>(width, 1))) {
    STEPSTONE_ASSERT(width >= 1 && channels >= 1);
}

STEPSTONE_KB_CLONES double BlockMeans::point(const float* segment, double* out) const {
    // the largest magnitude over eight lanes, as the bits of |value|: for
    // finite floats (and infinity) they order as the values do, and an
    // integer maximum vectorises where a float one (NaN rules) does not
    const std::size_t n = width_ * channels_;
    std::uint32_t lanes[8] = {};
    const auto magnitude = [](float v) {
        std::uint32_t bits;
        std::memcpy(&bits, &v, sizeof(bits));
        return bits & 0x7fffffffu;
    };
    std::size_t k = 0;
    for (; k + 8 <= n; k += 8)
        for (std::size_t j = 0; j < 8; ++j) lanes[j] = std::max(lanes[j], magnitude(segment[k + j]));
    std::uint32_t top = 0;
    for (; k < n; ++k) top = std::max(top, magnitude(segment[k]));
    for (const std::uint32_t lane : lanes) top = std::max(top, lane);
    float largest;
    std::memcpy(&largest, &top, sizeof(largest));

    // per block, the rows summed channel by channel in row order; four
    // channels at a time as a vector of doubles, the last four of a row
    // overlapping the previous ones when channels is not a multiple of 4 (an
    // overlapped channel is computed twice the same way). Each sum adds the
    // same terms in the same order as a plain loop, so the bits are those of
    // 0.0 + x_first + ... + x_last
    for (std::size_t b = 0; b < blocks_; ++b) {
        const std::size_t first = b * width_ / blocks_;
        const std::size_t end = (b + 1) * width_ / blocks_;
        double* p = out + b * channels_;
        if (channels_ >= 4) {
            for (std::size_t c0 = 0; c0 < channels_; c0 += 4) {
                const std::size_t c = std::min(c0, channels_ - 4);
                Quad sum = {};
                for (std::size_t t = first; t < end; ++t) {
                    Floats4 v;
                    std::memcpy(&v, segment + t * channels_ + c, sizeof(v));
                    sum += __builtin_convertvector(v, Quad);
                }
                std::memcpy(p + c, &sum, sizeof(sum));
            }
        } else {
            for (std::size_t c = 0; c < channels_; ++c) p[c] = 0.0;
            for (std::size_t t = first; t < end; ++t) {
                const float* row = segment + t * channels_;
                for (std::size_t c = 0; c < channels_; ++c) p[c] += static_cast<double>(row[c]);
            }
        }
        // sum / rows * sqrt(rows) = sum / sqrt(rows)
        const double scale = 1.0 / std::sqrt(static_cast<double>(end - first));
        for (std::size_t c = 0; c < channels_; ++c) p[c] *= scale;
    }
    return static_cast<double>(largest);
}

double squared_gap(const double* a, const double* b, std::size_t n) {
    double s[4] = {};
    std::size_t k = 0;
    for (; k + 4 <= n; k += 4)
        for (std::size_t j = 0; j < 4; ++j) {
            const double d = a[k + j] - b[k + j];
            s[j] += d * d;
        }
    for (std::size_t j = 0; k < n; ++k, ++j) {
        const double d = a[k] - b[k];
        s[j] += d * d;
    }
    return (s[0] + s[1]) + (s[2] + s[3]);
}

STEPSTONE_KB_CLONES float squared_gap(const float* a, const float* b, std::size_t n) {
    float s[8] = {};
    std::size_t k = 0;
    for (; k + 8 <= n; k += 8)
        for (std::size_t j = 0; j < 8; ++j) {
            const float d = a[k + j] - b[k + j];
            s[j] += d * d;
        }
    for (std::size_t j = 0; k < n; ++k, ++j) {
        const float d = a[k] - b[k];
        s[j] += d * d;
    }
    return ((s[0] + s[1]) + (s[2] + s[3])) + ((s[4] + s[5]) + (s[6] + s[7]));
}

}  // namespace stepstone::kb
