#include "core/portable_math_lanes.hpp"

#include "core/cpu.hpp"
#include "core/portable_math.hpp"
#if defined(__x86_64__) || defined(__i386__)
#define STEPSTONE_CORE_HAVE_AVX2_SINCOS 1
#include <immintrin.h>
#endif

#include "core/portable_math_constants.hpp"

namespace stepstone::portable {

namespace {

#ifdef STEPSTONE_CORE_HAVE_AVX2_SINCOS
// portable::sincos of x[0..3], every lane the scalar function's operations in its order
[[gnu::target("avx2")]] void sincos4(const double* x, double* s, double* c) {
    const __m256d vx = _mm256_loadu_pd(x);
    // nearbyint in the default rounding mode: to nearest, ties to even
    const __m256d k = _mm256_round_pd(_mm256_mul_pd(vx, _mm256_set1_pd(detail::kTwoOverPi)),
                                      _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC);
    __m256d r;
    __m256d sr;
    __m256d cr;
    detail::reduce(vx, k, r);
    detail::sincos_kernel(r, sr, cr);
    // the quadrant k mod 4 (|k| < 2^31: the 32-bit conversion is exact): odd quadrants swap sine
    // and cosine, quadrants 2 and 3 negate the sine, 1 and 2 the cosine
    const __m128i q = _mm256_cvtpd_epi32(k);
    const __m256i q64 = _mm256_cvtepi32_epi64(q);
    const __m256i one = _mm256_set1_epi64x(1);
    const __m256i two = _mm256_set1_epi64x(2);
    const __m256d swap = _mm256_castsi256_pd(_mm256_cmpeq_epi64(_mm256_and_si256(q64, one), one));
    const __m256i sign_bit = _mm256_set1_epi64x(static_cast<long long>(0x8000000000000000ull));
    const __m256d sin_sign =
        _mm256_castsi256_pd(_mm256_and_si256(_mm256_cmpeq_epi64(_mm256_and_si256(q64, two), two), sign_bit));
    const __m256i q1 = _mm256_add_epi64(q64, one);
    const __m256d cos_sign =
        _mm256_castsi256_pd(_mm256_and_si256(_mm256_cmpeq_epi64(_mm256_and_si256(q1, two), two), sign_bit));
    const __m256d vs = _mm256_xor_pd(_mm256_blendv_pd(sr, cr, swap), sin_sign);
    const __m256d vc = _mm256_xor_pd(_mm256_blendv_pd(cr, sr, swap), cos_sign);
    _mm256_storeu_pd(s, vs);
    _mm256_storeu_pd(c, vc);
}

// sincos4 of x[0..7] in one AVX-512 vector: the same operations, half the instructions, which
// lets twice as many angles' long chains of multiplies and adds be in flight at once
[[gnu::target("avx512f,avx512dq")]] void sincos8(const double* x, double* s, double* c) {
    const __m512d vx = _mm512_loadu_pd(x);
    // (the zero-masked forms: GCC 12's unmasked ones trip -Wuninitialized)
    const __m512d k = _mm512_maskz_roundscale_pd(0xFF, _mm512_mul_pd(vx, _mm512_set1_pd(detail::kTwoOverPi)),
                                                 _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC);
    __m512d r;
    __m512d sr;
    __m512d cr;
    detail::reduce(vx, k, r);
    detail::sincos_kernel(r, sr, cr);
    // the quadrant as in sincos4 (k integral: the conversion is exact), with masks: bit 0 swaps, bit 1 of q
    // negates the sine, of q + 1 the cosine
    const __m512i q = _mm512_maskz_cvtpd_epi64(0xFF, k);
    const __m512i one = _mm512_set1_epi64(1);
    const __m512i two = _mm512_set1_epi64(2);
    const __mmask8 swap = _mm512_test_epi64_mask(q, one);
    const __mmask8 negate_sine = _mm512_test_epi64_mask(q, two);
    const __mmask8 negate_cosine = _mm512_test_epi64_mask(_mm512_add_epi64(q, one), two);
    const __m512d sign =
        _mm512_castsi512_pd(_mm512_set1_epi64(static_cast<long long>(0x8000000000000000ull)));
    const __m512d vs = _mm512_mask_blend_pd(swap, sr, cr);
    const __m512d vc = _mm512_mask_blend_pd(swap, cr, sr);
    _mm512_storeu_pd(s, _mm512_mask_xor_pd(vs, negate_sine, vs, sign));
    _mm512_storeu_pd(c, _mm512_mask_xor_pd(vc, negate_cosine, vc, sign));
}
#endif

}  // namespace

void sincos_lanes_generic(const double* x, double* s, double* c, std::size_t count) {
    for (std::size_t i = 0; i < count; ++i) sincos(x[i], s[i], c[i]);
}

void sincos_lanes_avx2(const double* x, double* s, double* c, std::size_t count) {
    std::size_t i = 0;
#ifdef STEPSTONE_CORE_HAVE_AVX2_SINCOS
    if (avx2_kernels_allowed()) {
        for (; i + 4 <= count; i += 4) sincos4(x + i, s + i, c + i);
    }
#endif
    sincos_lanes_generic(x + i, s + i, c + i, count - i);
}

void sincos_lanes(const double* x, double* s, double* c, std::size_t count) {
    std::size_t i = 0;
#ifdef STEPSTONE_CORE_HAVE_AVX2_SINCOS
    if (avx512_kernels_allowed()) {
        for (; i + 8 <= count; i += 8) sincos8(x + i, s + i, c + i);
    }
#endif
    sincos_lanes_avx2(x + i, s + i, c + i, count - i);  // the rest: four a vector, then one by one
}

}  // namespace stepstone::portable
