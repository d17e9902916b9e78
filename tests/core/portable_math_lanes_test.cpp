// portable::sincos_lanes against the scalar portable::sincos, its oracle: the
// same bits on every argument, in the AVX2 build and the generic one, for
// every count (the vectors of four and the tail).
#include "core/portable_math_lanes.hpp"

#include <bit>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "core/portable_math.hpp"

using namespace stepstone;

namespace {

std::uint64_t bits(double x) { return std::bit_cast<std::uint64_t>(x); }

// the angles a run asks for (headings, heading - pi/2, turns), a wider band up to 2^20, and the
// edges: signed zeros, tiny and subnormal angles, multiples of pi/4 and pi/2 and their
// neighbours (where the quadrant's rounding turns), the ends of the heading range
std::vector<double> arguments() {
    std::vector<double> xs = {0.0, -0.0, 1e-300, -1e-300, 4.9e-324,        -4.9e-324,    1e-10,        -1e-10,
                              0.2, -0.2, M_PI,   -M_PI,   M_PI / 2 - M_PI, 0x1.fffffp19, -0x1.fffffp19};
    for (int k = -64; k <= 64; ++k) {
        for (const double base : {k * (M_PI / 4), k * (M_PI / 2), k * 0.5}) {
            double x = base;
            for (int i = 0; i < 3; ++i) x = std::nextafter(x, -INFINITY);
            for (int i = 0; i < 7; ++i, x = std::nextafter(x, INFINITY)) xs.push_back(x);
        }
    }
    std::mt19937_64 engine(46);
    const auto uniform = [&] { return static_cast<double>(engine() >> 11) * 0x1.0p-53; };
    for (int i = 0; i < 100000; ++i) {
        switch (i % 4) {
            case 0:
                xs.push_back((uniform() * 2.0 - 1.0) * M_PI);
                break;
            case 1:
                xs.push_back((uniform() * 2.0 - 1.0) * M_PI - M_PI / 2);
                break;
            case 2:
                xs.push_back((uniform() - 0.5) * 0.4);
                break;
            default:
                xs.push_back((uniform() * 2.0 - 1.0) * std::ldexp(1.0, static_cast<int>(engine() % 21)));
                break;
        }
    }
    return xs;
}

}  // namespace

TEST_CASE("sincos_lanes gives portable::sincos's bits on every argument, AVX-512, AVX2 and generic builds",
          "[core][math]") {
    const std::vector<double> xs = arguments();
    std::vector<double> s(xs.size());
    std::vector<double> c(xs.size());
    std::vector<double> as(xs.size());
    std::vector<double> ac(xs.size());
    std::vector<double> gs(xs.size());
    std::vector<double> gc(xs.size());
    portable::sincos_lanes(xs.data(), s.data(), c.data(), xs.size());
    portable::sincos_lanes_avx2(xs.data(), as.data(), ac.data(), xs.size());
    portable::sincos_lanes_generic(xs.data(), gs.data(), gc.data(), xs.size());
    std::size_t differences = 0;
    for (std::size_t i = 0; i < xs.size(); ++i) {
        double es = 0.0;
        double ec = 0.0;
        portable::sincos(xs[i], es, ec);
        const bool same = bits(s[i]) == bits(es) && bits(c[i]) == bits(ec) && bits(as[i]) == bits(es) &&
                          bits(ac[i]) == bits(ec) && bits(gs[i]) == bits(es) && bits(gc[i]) == bits(ec);
        if (!same && differences++ < 5) {
            UNSCOPED_INFO("x = " << std::hexfloat << xs[i] << ": lanes " << s[i] << ", " << c[i]
                                 << "; scalar " << es << ", " << ec);
        }
    }
    CHECK(differences == 0);
}

TEST_CASE("sincos_lanes fills every count, tails included, and leaves the rest of the arrays alone",
          "[core][math]") {
    const std::vector<double> xs = {0.1, -2.5, 3.0, 1.0, -0.7, 2.2, -3.1, 0.05, 1.5, -1.5, 0.3, 2.9, -0.4};
    for (std::size_t count = 0; count <= xs.size(); ++count) {
        std::vector<double> s(xs.size() + 1, 7.0);
        std::vector<double> c(xs.size() + 1, 7.0);
        portable::sincos_lanes(xs.data(), s.data(), c.data(), count);
        for (std::size_t i = 0; i < count; ++i) {
            double es = 0.0;
            double ec = 0.0;
            portable::sincos(xs[i], es, ec);
            REQUIRE(bits(s[i]) == bits(es));
            REQUIRE(bits(c[i]) == bits(ec));
        }
        for (std::size_t i = count; i < s.size(); ++i) {
            REQUIRE(s[i] == 7.0);
            REQUIRE(c[i] == 7.0);
        }
    }
}

TEST_CASE("sincos_lanes of a NaN or an infinity is NaN, as the scalar function's", "[core][math]") {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    // a vector of eight (AVX-512), one of four (AVX2) and a lane alone
    const double xs[13] = {nan, INFINITY, -INFINITY, 1.0,       1.0, 1.0, 1.0,
                           1.0, nan,      INFINITY,  -INFINITY, 1.0, nan};
    double s[13];
    double c[13];
    portable::sincos_lanes(xs, s, c, 13);
    for (int i = 0; i < 13; ++i) {
        if (xs[i] == 1.0) {
            CHECK(s[i] == portable::sin(1.0));
        } else {
            CHECK(std::isnan(s[i]));
            CHECK(std::isnan(c[i]));
        }
    }
}
