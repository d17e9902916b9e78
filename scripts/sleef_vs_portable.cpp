// SLEEF's vector sincos (Debian's libsleef-dev 3.5.1) against stepstone's own
// portable::sincos and its lanes (core/portable_math_lanes): accuracy in ulp
// against long double, agreement between SLEEF's builds for different
// instruction sets, and time per angle. Not part of the build (SLEEF is not a
// dependency); the numbers are in docs/performance.md. From the repository root:
//   apt-get install libsleef-dev
//   g++ -O2 -std=c++20 -ffp-contract=off -Ilib -c lib/core/portable_math.cpp lib/core/portable_math_lanes.cpp
//   g++ -O2 -std=c++20 -ffp-contract=off -mavx512f -mfma -Ilib scripts/sleef_vs_portable.cpp \
//       portable_math.o portable_math_lanes.o -lsleef -o /tmp/sleef_vs_portable
// (the SLEEF vector types are declared only where the compiler targets their instruction sets;
// stepstone's functions keep the project's flags)
//   /tmp/sleef_vs_portable
#include <immintrin.h>
#include <sleef.h>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "core/portable_math.hpp"
#include "core/portable_math_lanes.hpp"

using namespace stepstone;

namespace {

double ulps(double value, long double exact) {
    const double nearest = static_cast<double>(exact);
    const double ulp = std::nextafter(std::fabs(nearest), INFINITY) - std::fabs(nearest);
    return static_cast<double>(std::fabs(static_cast<long double>(value) - exact) / ulp);
}

// fills s and c for n angles (n a multiple of 8)
using Batch = std::function<void(const double*, double*, double*, std::size_t)>;

[[gnu::target("avx2,fma")]] void sleef_u10_avx2(const double* x, double* s, double* c, std::size_t n) {
    for (std::size_t i = 0; i < n; i += 4) {
        const Sleef___m256d_2 r = Sleef_sincosd4_u10avx2(_mm256_loadu_pd(x + i));
        _mm256_storeu_pd(s + i, r.x);
        _mm256_storeu_pd(c + i, r.y);
    }
}
[[gnu::target("avx2,fma")]] void sleef_u35_avx2(const double* x, double* s, double* c, std::size_t n) {
    for (std::size_t i = 0; i < n; i += 4) {
        const Sleef___m256d_2 r = Sleef_sincosd4_u35avx2(_mm256_loadu_pd(x + i));
        _mm256_storeu_pd(s + i, r.x);
        _mm256_storeu_pd(c + i, r.y);
    }
}
[[gnu::target("avx")]] void sleef_u10_avx(const double* x, double* s, double* c, std::size_t n) {
    for (std::size_t i = 0; i < n; i += 4) {
        const Sleef___m256d_2 r = Sleef_sincosd4_u10avx(_mm256_loadu_pd(x + i));
        _mm256_storeu_pd(s + i, r.x);
        _mm256_storeu_pd(c + i, r.y);
    }
}
void sleef_u10_sse2(const double* x, double* s, double* c, std::size_t n) {
    for (std::size_t i = 0; i < n; i += 2) {
        const Sleef___m128d_2 r = Sleef_sincosd2_u10sse2(_mm_loadu_pd(x + i));
        _mm_storeu_pd(s + i, r.x);
        _mm_storeu_pd(c + i, r.y);
    }
}
[[gnu::target("avx2,fma")]] void sleef_u10_avx2128(const double* x, double* s, double* c, std::size_t n) {
    for (std::size_t i = 0; i < n; i += 2) {
        const Sleef___m128d_2 r = Sleef_sincosd2_u10avx2128(_mm_loadu_pd(x + i));
        _mm_storeu_pd(s + i, r.x);
        _mm_storeu_pd(c + i, r.y);
    }
}
[[gnu::target("avx512f")]] void sleef_u10_avx512f(const double* x, double* s, double* c, std::size_t n) {
    for (std::size_t i = 0; i < n; i += 8) {
        const Sleef___m512d_2 r = Sleef_sincosd8_u10avx512f(_mm512_loadu_pd(x + i));
        _mm512_storeu_pd(s + i, r.x);
        _mm512_storeu_pd(c + i, r.y);
    }
}
[[gnu::target("avx512f")]] void sleef_u10_avx512fnofma(const double* x, double* s, double* c, std::size_t n) {
    for (std::size_t i = 0; i < n; i += 8) {
        const Sleef___m512d_2 r = Sleef_sincosd8_u10avx512fnofma(_mm512_loadu_pd(x + i));
        _mm512_storeu_pd(s + i, r.x);
        _mm512_storeu_pd(c + i, r.y);
    }
}
void sleef_u10_purec(const double* x, double* s, double* c, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) {
        const Sleef_double_2 r = Sleef_sincosd1_u10purec(x[i]);
        s[i] = r.x;
        c[i] = r.y;
    }
}
void sleef_u10_purecfma(const double* x, double* s, double* c, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) {
        const Sleef_double_2 r = Sleef_sincosd1_u10purecfma(x[i]);
        s[i] = r.x;
        c[i] = r.y;
    }
}
void portable_scalar(const double* x, double* s, double* c, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) portable::sincos(x[i], s[i], c[i]);
}
void portable_lanes(const double* x, double* s, double* c, std::size_t n) {
    portable::sincos_lanes(x, s, c, n);
}
void glibc(const double* x, double* s, double* c, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) ::sincos(x[i], &s[i], &c[i]);
}

struct Entry {
    const char* name;
    Batch batch;
};

}  // namespace

int main() {
    // the angles of a run: headings in (-pi, pi], heading - pi/2, turns up to 0.2 rad
    std::mt19937_64 engine(46);
    const auto uniform = [&] { return static_cast<double>(engine() >> 11) * 0x1.0p-53; };
    const std::size_t n = 1 << 20;
    std::vector<double> xs(n);
    for (std::size_t i = 0; i < n; ++i) {
        xs[i] = i % 3 == 0   ? (uniform() * 2 - 1) * M_PI
                : i % 3 == 1 ? (uniform() * 2 - 1) * M_PI - M_PI / 2
                             : (uniform() - 0.5) * 0.4;
    }
    const std::vector<Entry> entries = {
        {"portable::sincos (scalar)", portable_scalar},
        {"portable::sincos_lanes (AVX2)", portable_lanes},
        {"glibc sincos", glibc},
        {"SLEEF u10 avx2", sleef_u10_avx2},
        {"SLEEF u35 avx2", sleef_u35_avx2},
        {"SLEEF u10 avx", sleef_u10_avx},
        {"SLEEF u10 sse2", sleef_u10_sse2},
        {"SLEEF u10 avx2128", sleef_u10_avx2128},
        {"SLEEF u10 avx512f", sleef_u10_avx512f},
        {"SLEEF u10 avx512fnofma", sleef_u10_avx512fnofma},
        {"SLEEF u10 purec", sleef_u10_purec},
        {"SLEEF u10 purecfma", sleef_u10_purecfma},
    };
    std::vector<double> ref_s(n), ref_c(n), s(n), c(n);
    sleef_u10_avx2(xs.data(), ref_s.data(), ref_c.data(), n);
    std::vector<double> port_s(n), port_c(n);
    portable_scalar(xs.data(), port_s.data(), port_c.data(), n);
    std::printf("%-30s %9s %14s %14s %10s\n", "function", "max ulp", "!= SLEEF avx2", "!= portable",
                "ns/angle");
    for (const Entry& e : entries) {
        e.batch(xs.data(), s.data(), c.data(), n);
        double worst = 0.0;
        std::size_t vs_sleef = 0, vs_portable = 0;
        for (std::size_t i = 0; i < n; ++i) {
            const long double x = xs[i];
            worst = std::max({worst, ulps(s[i], sinl(x)), ulps(c[i], cosl(x))});
            const auto b = [](double v) { return std::bit_cast<std::uint64_t>(v); };
            vs_sleef += b(s[i]) != b(ref_s[i]) || b(c[i]) != b(ref_c[i]);
            vs_portable += b(s[i]) != b(port_s[i]) || b(c[i]) != b(port_c[i]);
        }
        // time: the best of 7 passes over 8192 angles (in cache), ns per angle
        double best = 1e30;
        for (int pass = 0; pass < 7; ++pass) {
            const auto t0 = std::chrono::steady_clock::now();
            for (int rep = 0; rep < 64; ++rep)
                e.batch(xs.data() + (rep % 16) * 8192, s.data(), c.data(), 8192);
            const auto t1 = std::chrono::steady_clock::now();
            best = std::min(best, std::chrono::duration<double, std::nano>(t1 - t0).count() / (64.0 * 8192));
        }
        std::printf("%-30s %9.3f %14zu %14zu %10.2f\n", e.name, worst, vs_sleef, vs_portable, best);
    }
    std::printf("(%zu angles: headings, heading - pi/2, turns)\n", n);
}
