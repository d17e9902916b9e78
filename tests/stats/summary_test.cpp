#include "stats/summary.hpp"

#include <catch2/catch.hpp>
#include <limits>
#include <vector>

#include "core/error.hpp"

using namespace stepstone;
using namespace stepstone::stats;

// Type-7 quartiles by hand: h = (n - 1) q, q-quantile = x_l + (h - l)(x_{l+1} - x_l)
// with l = floor(h) on the sorted values. tests/stats/oracle.py gives the same
// numbers and checked them against numpy 1.24.2 percentile (its default is type 7).

TEST_CASE("summarize: 1 2 3 4", "[stats]") {
    // q1: h = 0.75 -> 1 + 0.75 = 1.75; median: h = 1.5 -> 2.5; q3: h = 2.25 -> 3.25
    const Summary s = summarize(std::vector<double>{4, 2, 1, 3});
    CHECK(s.n == 4);
    CHECK(s.min == 1.0);
    CHECK(s.q1 == 1.75);
    CHECK(s.median == 2.5);
    CHECK(s.q3 == 3.25);
    CHECK(s.max == 4.0);
    CHECK(s.mean == 2.5);
}

TEST_CASE("summarize: odd count, single value", "[stats]") {
    // 1 2 3: q1 h = 0.5 -> 1.5, median h = 1 -> 2, q3 h = 1.5 -> 2.5
    const Summary s = summarize(std::vector<double>{3, 1, 2});
    CHECK(s.q1 == 1.5);
    CHECK(s.median == 2.0);
    CHECK(s.q3 == 2.5);
    CHECK(s.mean == 2.0);

    const Summary one = summarize(std::vector<double>{7});
    CHECK(one.n == 1);
    CHECK(one.min == 7.0);
    CHECK(one.q1 == 7.0);
    CHECK(one.median == 7.0);
    CHECK(one.q3 == 7.0);
    CHECK(one.max == 7.0);
    CHECK(one.mean == 7.0);
}

TEST_CASE("summarize: ten values with repeats", "[stats]") {
    // sorted: 0 0 0 1 2.5 4 5 5 9 10
    // q1: h = 2.25 -> 0 + 0.25 (1 - 0) = 0.25; median: h = 4.5 -> 2.5 + 0.5 (4 - 2.5) = 3.25;
    // q3: h = 6.75 -> 5 + 0.75 (5 - 5) = 5; mean 36.5 / 10 = 3.65
    const Summary s = summarize(std::vector<double>{0, 0, 0, 1, 5, 5, 9, 10, 2.5, 4});
    CHECK(s.n == 10);
    CHECK(s.min == 0.0);
    CHECK(s.q1 == Approx(0.25).epsilon(1e-15));
    CHECK(s.median == Approx(3.25).epsilon(1e-15));
    CHECK(s.q3 == 5.0);
    CHECK(s.max == 10.0);
    CHECK(s.mean == Approx(3.65).epsilon(1e-15));
}

TEST_CASE("summarize: infinities between equal neighbours stay finite", "[stats]") {
    const double inf = std::numeric_limits<double>::infinity();
    // sorted 1 1 1 1 inf: q1 h = 1 -> 1, median h = 2 -> 1, q3 h = 3 -> 1
    const Summary s = summarize(std::vector<double>{1, inf, 1, 1, 1});
    CHECK(s.q1 == 1.0);
    CHECK(s.median == 1.0);
    CHECK(s.q3 == 1.0);
    CHECK(s.max == inf);
}

TEST_CASE("summarize: bad input throws DataError", "[stats]") {
    CHECK_THROWS_AS(summarize(std::vector<double>{}), DataError);
    CHECK_THROWS_AS(summarize(std::vector<double>{1, std::numeric_limits<double>::quiet_NaN()}), DataError);
}

TEST_CASE("count_at_least: by hand", "[stats]") {
    const std::vector<double> v{0, 0.5, 1, 1, 23.0 / 24.0};
    CHECK(count_at_least(v, 1.0) == 2);
    CHECK(count_at_least(v, 0.0) == 5);
    CHECK(count_at_least(v, 0.5) == 4);
    CHECK(count_at_least(v, 2.0) == 0);
    CHECK(count_at_least(v, -std::numeric_limits<double>::infinity()) == 5);
    CHECK(count_at_least(std::vector<double>{}, 1.0) == 0);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    CHECK_THROWS_AS(count_at_least(v, nan), DataError);
    CHECK_THROWS_AS(count_at_least(std::vector<double>{1, nan}, 0.0), DataError);
}

TEST_CASE("median: the middle value, or the mean of the two middle ones, as summarize gives it", "[stats]") {
    const std::vector<double> odd{5, 1, 3};
    const std::vector<double> even{4, 1, 3, 2};
    CHECK(median(odd) == 3.0);
    CHECK(median(even) == 2.5);
    // 0.1 + 0.2 is not 0.3 in binary: both halves are added as the old median_of did, 0.5 (a + b)
    const std::vector<double> tenths{0.2, 0.1};
    CHECK(median(tenths) == 0.5 * (0.1 + 0.2));
    CHECK(median(even) == summarize(even).median);
    CHECK_THROWS_AS(median(std::vector<double>{}), DataError);
    CHECK_THROWS_AS(median(std::vector<double>{1.0, std::numeric_limits<double>::quiet_NaN()}), DataError);
}
