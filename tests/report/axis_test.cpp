// Axis ticks against hand-computed values (Heckbert's nice numbers).

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "report/axis.hpp"

using stepstone::report::nice_ticks;
using stepstone::report::Scale;

namespace {

std::vector<std::string> labels(const stepstone::report::Ticks& ticks) {
    std::vector<std::string> out;
    for (const double v : ticks.values) out.push_back(ticks.label(v));
    return out;
}

}  // namespace

TEST_CASE("ticks of a reward axis are tenths", "[report]") {
    // the range 0.625 rounds up to nice(0.625) = 1; 1 / (6 - 1) = 0.2, already round
    const auto ticks = nice_ticks(0.0, 0.625, 6);
    CHECK(ticks.step == Approx(0.2));
    CHECK(labels(ticks) == std::vector<std::string>{"0.0", "0.2", "0.4", "0.6", "0.8"});
    CHECK(ticks.low == 0.0);
    CHECK(ticks.high == Approx(0.8));
}

TEST_CASE("ticks of a generation axis are thousands", "[report]") {
    // nice(4000) = 5000 (4 rounds up to 5); 5000 / 7 = 714 rounds to 1000
    const auto ticks = nice_ticks(0.0, 4000.0, 8);
    CHECK(ticks.step == 1000.0);
    CHECK(labels(ticks) == std::vector<std::string>{"0", "1000", "2000", "3000", "4000"});
    CHECK(ticks.decimals == 0);
}

TEST_CASE("ticks cover a range that crosses zero at multiples of the step", "[report]") {
    // nice(10) = 10, 10 / 5 = 2; floor(-3 / 2) * 2 = -4, ceil(7 / 2) * 2 = 8
    const auto ticks = nice_ticks(-3.0, 7.0, 6);
    CHECK(labels(ticks) == std::vector<std::string>{"-4", "-2", "0", "2", "4", "6", "8"});
}

TEST_CASE("ticks of the unit interval and of small ranges print exactly", "[report]") {
    CHECK(labels(nice_ticks(0.0, 1.0, 6)) == std::vector<std::string>{"0.0", "0.2", "0.4", "0.6", "0.8", "1.0"});
    // nice(0.3) = 0.5, 0.5 / 5 = 0.1: 3 x 0.1 is 0.30000000000000004 in binary, printed 0.3
    CHECK(labels(nice_ticks(0.0, 0.3, 6)) == std::vector<std::string>{"0.0", "0.1", "0.2", "0.3"});
    // nice(0.02) = 0.02, 0.02 / 5 = 0.004 rounds to 0.005
    CHECK(labels(nice_ticks(0.0, 0.02, 6)) ==
          std::vector<std::string>{"0.000", "0.005", "0.010", "0.015", "0.020"});
}

TEST_CASE("degenerate ranges get usable ticks", "[report]") {
    // one value: widened by 1 each way, nice(2) = 2, 2 / 5 = 0.4 rounds to 0.5
    CHECK(labels(nice_ticks(5.0, 5.0, 6)) == std::vector<std::string>{"4.0", "4.5", "5.0", "5.5", "6.0"});
    CHECK(labels(nice_ticks(0.0, 0.0, 6)) == labels(nice_ticks(0.0, 1.0, 6)));
    CHECK(labels(nice_ticks(1.0, 0.0, 6)) == labels(nice_ticks(0.0, 1.0, 6)));
    const double nan = std::numeric_limits<double>::quiet_NaN();
    CHECK(labels(nice_ticks(nan, 3.0, 6)) == labels(nice_ticks(0.0, 1.0, 6)));
    CHECK(labels(nice_ticks(-0.0, 1.0, 6)).front() == "0.0");
}

TEST_CASE("ticks always enclose the data and stay near the asked count", "[report]") {
    for (const auto& [low, high] : std::vector<std::pair<double, double>>{
             {0.0, 0.041}, {0.0, 1.0 / 24.0}, {3.0, 3001.0}, {-0.5, 0.25}, {120.0, 980.0}, {0.0, 149233.0}}) {
        const auto ticks = nice_ticks(low, high, 6);
        CAPTURE(low, high, ticks.step);
        CHECK(ticks.low <= low);
        CHECK(ticks.high >= high);
        CHECK(ticks.values.size() >= 3);
        CHECK(ticks.values.size() <= 12);
        // every step is 1, 2 or 5 times a power of ten
        const double mantissa = ticks.step / std::pow(10.0, std::floor(std::log10(ticks.step)));
        CHECK((mantissa == Approx(1.0) || mantissa == Approx(2.0) || mantissa == Approx(5.0)));
    }
}

TEST_CASE("a scale maps data linearly onto pixels", "[report]") {
    const Scale x{0.0, 10.0, 100.0, 200.0};
    CHECK(x(5.0) == 150.0);
    CHECK(x(0.0) == 100.0);
    const Scale y{0.0, 1.0, 400.0, 50.0};  // pixels grow downwards
    CHECK(y(0.5) == 225.0);
    CHECK(y(1.0) == 50.0);
}
