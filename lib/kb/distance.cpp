#include "kb/distance.hpp"

#include <cstdint>
#include <limits>
#if defined(__x86_64__) || defined(__i386__)
#define STEPSTONE_KB_HAVE_AVX2_DISTANCE 1
#include <immintrin.h>
#endif

#include "kb/detail/simd.hpp"

namespace stepstone::kb {

namespace {

// values between two checks of the bound in squared_distance_up_to
constexpr std::size_t kCheckEvery = 32;

struct Lanes {
    double l[kDistanceLanes] = {};

    // adds the squared differences of values [begin, end); begin is a
    // multiple of kDistanceLanes, so value k goes to lane k % 8
    void add(const float* a, const float* b, std::size_t begin, std::size_t end) {
        std::size_t k = begin;
        for (; k + kDistanceLanes <= end; k += kDistanceLanes) {
            for (std::size_t j = 0; j < kDistanceLanes; ++j) {
                const double d = static_cast<double>(a[k + j]) - static_cast<double>(b[k + j]);
                l[j] += d * d;
            }
        }
        for (std::size_t j = 0; k < end; ++k, ++j) {
            const double d = static_cast<double>(a[k]) - static_cast<double>(b[k]);
            l[j] += d * d;
        }
    }

    double total() const { return ((l[0] + l[1]) + (l[2] + l[3])) + ((l[4] + l[5]) + (l[6] + l[7])); }
};

#ifdef STEPSTONE_KB_HAVE_AVX2_DISTANCE
// the squares of x - y (8 floats each, as doubles) added to lanes 0-3 (low) and 4-7 (high)
[[gnu::target("avx2"), gnu::always_inline]] inline void add_squares(const __m256& x, const __m256& y,
                                                                    __m256d& low, __m256d& high) {
    const __m256d d_low =
        _mm256_sub_pd(_mm256_cvtps_pd(_mm256_castps256_ps128(x)), _mm256_cvtps_pd(_mm256_castps256_ps128(y)));
    const __m256d d_high = _mm256_sub_pd(_mm256_cvtps_pd(_mm256_extractf128_ps(x, 1)),
                                         _mm256_cvtps_pd(_mm256_extractf128_ps(y, 1)));
    low = _mm256_add_pd(low, _mm256_mul_pd(d_low, d_low));
    high = _mm256_add_pd(high, _mm256_mul_pd(d_high, d_high));
}

// Lanes::total() of the two vectors: (l0 + l1) + (l2 + l3) beside (l4 + l5) + (l6 + l7), then their sum
[[gnu::target("avx2"), gnu::always_inline]] inline double lanes_total(const __m256d& low,
                                                                      const __m256d& high) {
    const __m256d pairs = _mm256_hadd_pd(low, high);  // l0+l1, l4+l5, l2+l3, l6+l7
    const __m128d halves = _mm_add_pd(_mm256_castpd256_pd128(pairs), _mm256_extractf128_pd(pairs, 1));
    return _mm_cvtsd_f64(_mm_add_sd(halves, _mm_unpackhi_pd(halves, halves)));
}

// squared_distance_up_to with lanes 0-3 and 4-7 in two vectors: the same squares added to the
// same lanes in the same order, and the same totals. A last block of fewer than 8 values is
// loaded with zeros past its end: their squares, +0, leave the lanes as they are.
[[gnu::target("avx2")]] double squared_distance_up_to_avx2(const float* a, const float* b, std::size_t dim,
                                                           double bound) {
    __m256d low = _mm256_setzero_pd();
    __m256d high = _mm256_setzero_pd();
    std::size_t k = 0;
    while (k < dim) {
        const std::size_t end = k + kCheckEvery < dim ? k + kCheckEvery : dim;
        for (; k + kDistanceLanes <= end; k += kDistanceLanes) {
            add_squares(_mm256_loadu_ps(a + k), _mm256_loadu_ps(b + k), low, high);
        }
        if (k < end) {
            alignas(32) std::int32_t lanes[kDistanceLanes];
            for (std::size_t j = 0; j < kDistanceLanes; ++j) lanes[j] = j < end - k ? -1 : 0;
            const __m256i mask = _mm256_load_si256(reinterpret_cast<const __m256i*>(lanes));
            add_squares(_mm256_maskload_ps(a + k, mask), _mm256_maskload_ps(b + k, mask), low, high);
            k = end;
        }
        if (k < dim) {
            const double partial = lanes_total(low, high);
            if (partial > bound) return partial;
        }
    }
    return lanes_total(low, high);
}
#endif

double squared_distance_generic(const float* a, const float* b, std::size_t dim) {
    Lanes lanes;
    lanes.add(a, b, 0, dim);
    return lanes.total();
}

}  // namespace

double squared_distance(const float* a, const float* b, std::size_t dim) {
#ifdef STEPSTONE_KB_HAVE_AVX2_DISTANCE
    if (detail::use_avx2())
        return squared_distance_up_to_avx2(a, b, dim, std::numeric_limits<double>::infinity());
#endif
    return squared_distance_generic(a, b, dim);
}

double squared_distance_up_to(const float* a, const float* b, std::size_t dim, double bound) {
#ifdef STEPSTONE_KB_HAVE_AVX2_DISTANCE
    if (detail::use_avx2()) return squared_distance_up_to_avx2(a, b, dim, bound);
#endif
    Lanes lanes;
    std::size_t k = 0;
    // a partial total never exceeds the full one: every lane only grows
    // (adding a square rounds to a value >= the lane) and the final sum is
    // monotone in each lane
    while (k < dim) {
        const std::size_t end = k + kCheckEvery < dim ? k + kCheckEvery : dim;
        lanes.add(a, b, k, end);
        k = end;
        if (k < dim) {
            const double partial = lanes.total();
            if (partial > bound) return partial;
        }
    }
    return lanes.total();
}

}  // namespace stepstone::kb
