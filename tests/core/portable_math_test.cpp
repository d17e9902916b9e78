// core/portable_math against long double's sinl, cosl, atan2l and powl (64-bit
// mantissas, an oracle 2^11 times finer than the results checked), on the
// arguments a run gives them.
#include "core/portable_math.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <random>

using namespace stepstone;

namespace {

// distance in units in the last place of `exact` rounded to double
double ulps(double value, long double exact) {
    const double nearest = static_cast<double>(exact);
    const double ulp = std::nextafter(std::fabs(nearest), INFINITY) - std::fabs(nearest);
    return static_cast<double>(std::fabs(static_cast<long double>(value) - exact) / ulp);
}

// a fixed stream of doubles in [0, 1): the standard's Mersenne Twister, top 53 bits
struct Uniform {
    std::mt19937_64 engine{20261206};
    double next() { return static_cast<double>(engine() >> 11) * 0x1.0p-53; }
};

}  // namespace

TEST_CASE("portable sin and cos are within 1.5 ulp on headings and turns, and odd and even bit for bit",
          "[core][math]") {
    Uniform uniform;
    double worst = 0.0;
    for (int i = 0; i < 200000; ++i) {
        // headings in (-pi, pi], heading - pi/2, turns up to 0.2 rad, and a wider band
        const double x = i % 4 == 3 ? (uniform.next() - 0.5) * 0.4 : (uniform.next() * 2.0 - 1.0) * 7.0;
        double s = 0.0;
        double c = 0.0;
        portable::sincos(x, s, c);
        worst = std::max(
            {worst, ulps(s, sinl(static_cast<long double>(x))), ulps(c, cosl(static_cast<long double>(x)))});
        double ns = 0.0;
        double nc = 0.0;
        portable::sincos(-x, ns, nc);
        REQUIRE(ns == -s);
        REQUIRE(nc == c);
        REQUIRE(portable::sin(x) == s);
        REQUIRE(portable::cos(x) == c);
    }
    INFO("largest error: " << worst << " ulp");
    CHECK(worst <= 1.5);
    double s = 1.0;
    double c = 0.0;
    portable::sincos(0.0, s, c);
    CHECK(s == 0.0);
    CHECK(c == 1.0);
    // the quadrants: sin and cos of multiples of pi/2 land on their exact values within 1e-16
    for (int k = -8; k <= 8; ++k) {
        portable::sincos(k * (M_PI / 2), s, c);
        const int q = ((k % 4) + 4) % 4;
        CHECK(std::fabs(s - (q == 1 ? 1.0 : q == 3 ? -1.0 : 0.0)) < 1e-15);
        CHECK(std::fabs(c - (q == 0 ? 1.0 : q == 2 ? -1.0 : 0.0)) < 1e-15);
    }
}

TEST_CASE("portable pow is within 1.5 ulp on the polynomial mutation's arguments, 2e-15 relative beyond",
          "[core][math]") {
    Uniform uniform;
    double worst = 0.0;
    double worst_wide = 0.0;
    for (int i = 0; i < 200000; ++i) {
        // (2r)^(1 / (eta + 1)) for r in [0, 0.5) and eta from 0 to 40
        const double base = uniform.next();
        const double exponent = 1.0 / (1.0 + (i % 41));
        const double value = portable::pow(base, exponent);
        if (base == 0.0) {
            REQUIRE(value == 0.0);
            continue;
        }
        worst = std::max(
            worst, ulps(value, powl(static_cast<long double>(base), static_cast<long double>(exponent))));
        // wider: bases to 1000 and exponents to 8, so that |y log b| reaches 55
        const double wide_base = uniform.next() * 1000.0 + 1e-300;
        const double wide_exponent = uniform.next() * 8.0 + 1e-3;
        const long double exact =
            powl(static_cast<long double>(wide_base), static_cast<long double>(wide_exponent));
        worst_wide =
            std::max(worst_wide,
                     static_cast<double>(std::fabs(portable::pow(wide_base, wide_exponent) - exact) / exact));
    }
    INFO("largest error: " << worst << " ulp; wider arguments: " << worst_wide << " relative");
    CHECK(worst <= 1.5);
    CHECK(worst_wide <= 2e-15);
    CHECK(portable::pow(0.0, 0.25) == 0.0);
    CHECK(portable::pow(1.0, 0.25) == 1.0);
    CHECK(portable::pow(0.25, 0.5) == 0.5);
    CHECK(portable::pow(0.125, 1.0 / 3.0) == Approx(0.5).epsilon(1e-15));
}

TEST_CASE("portable atan2 is within 2 ulp in every quadrant, with std::atan2's signed zeros and axes",
          "[core][math]") {
    Uniform uniform;
    double worst = 0.0;
    for (int i = 0; i < 200000; ++i) {
        // offsets from the robot to a wall's vertex or closest point: both signs, scales 2^-20 to 2^20
        const double y = (uniform.next() - 0.5) * std::ldexp(1.0, static_cast<int>(uniform.next() * 40) - 20);
        const double x = (uniform.next() - 0.5) * std::ldexp(1.0, static_cast<int>(uniform.next() * 40) - 20);
        worst = std::max(worst, ulps(portable::atan2(y, x),
                                     atan2l(static_cast<long double>(y), static_cast<long double>(x))));
    }
    INFO("largest error: " << worst << " ulp");
    CHECK(worst <= 2.0);
    // the axes, the diagonals and the zeros, as C's atan2 defines them
    const double pi = 3.14159265358979323846;
    CHECK(portable::atan2(0.0, 1.0) == 0.0);
    CHECK(std::signbit(portable::atan2(-0.0, 1.0)));
    CHECK(portable::atan2(0.0, -1.0) == pi);
    CHECK(portable::atan2(-0.0, -1.0) == -pi);
    CHECK(portable::atan2(0.0, -0.0) == pi);
    CHECK(portable::atan2(1.0, 0.0) == pi / 2);
    CHECK(portable::atan2(-1.0, 0.0) == -pi / 2);
    CHECK(portable::atan2(1.0, 1.0) == pi / 4);
    CHECK(portable::atan2(-2.0, -2.0) == -3 * pi / 4);
    CHECK(portable::atan2(1.0, INFINITY) == 0.0);
    CHECK(portable::atan2(INFINITY, 1.0) == pi / 2);
    CHECK(std::isnan(portable::atan2(NAN, 1.0)));
    // magnitudes whose sum would overflow
    CHECK(portable::atan2(1e308, 1e308) == pi / 4);
    CHECK(portable::atan2(-1.5e308, 1e308) == Approx(-std::atan(1.5)).epsilon(1e-15));
}
