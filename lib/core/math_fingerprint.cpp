#include "core/math_fingerprint.hpp"

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>

namespace stepstone {

namespace {

// 64-bit FNV-1a over a value's bits
struct Fnv {
    std::uint64_t state = 0xcbf29ce484222325ULL;
    void add(double value) {
        auto bits = std::bit_cast<std::uint64_t>(value);
        for (int i = 0; i < 8; ++i, bits >>= 8) {
            state ^= bits & 0xffU;
            state *= 0x100000001b3ULL;
        }
    }
};

// a fixed sequence of doubles in [0, 1): xorshift64, top 53 bits
struct Uniform {
    std::uint64_t state = 0x9e3779b97f4a7c15ULL;
    double next() {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        return static_cast<double>(state >> 11) * 0x1.0p-53;
    }
};

// volatile inputs keep the compiler from folding or merging the calls
std::string compute() {
    constexpr int kAngles = 16384;  // about 20 sin and 20 cos results differ between glibc's builds
    constexpr int kPowers = 16384;  // about 10 differ
    constexpr int kPlanar = 4096;
    constexpr double kPi = 3.14159265358979323846;
    Fnv hash;
    Uniform uniform;
    for (int i = 0; i < kAngles; ++i) {
        volatile double angle = (uniform.next() * 4.0 - 2.0) * kPi;  // headings, heading - pi/2, turns
        hash.add(std::sin(angle));
        hash.add(std::cos(angle));
    }
    for (int i = 0; i < kPowers; ++i) {
        // the polynomial mutation: (2r)^(1 / (eta + 1)) for r in [0, 0.5), eta from 5 to 30
        volatile double base = uniform.next();
        volatile double exponent = 1.0 / (5.0 + static_cast<double>(i % 26) + 1.0);
        hash.add(std::pow(base, exponent));
    }
    for (int i = 0; i < kPlanar; ++i) {
        volatile double dx = uniform.next() * 1200.0 - 600.0;
        volatile double dy = uniform.next() * 1200.0 - 600.0;
        hash.add(std::atan2(dy, dx));
        hash.add(std::hypot(dx, dy));
    }
    char text[17];
    std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash.state));
    return text;
}

}  // namespace

const std::string& math_fingerprint() {
    static const std::string fingerprint = compute();
    return fingerprint;
}

}  // namespace stepstone
