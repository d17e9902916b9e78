#include <catch2/catch.hpp>

#include <algorithm>
#include <vector>

#include "core/error.hpp"
#include "core/rng.hpp"
#include "evo/selection.hpp"

using namespace stepstone;
using namespace stepstone::evo;
using Catch::Matchers::Equals;

TEST_CASE("the tournament prefers dominance, then crowding, then a coin", "[evo][selection]") {
    const Objectives objectives{{1, 1}, {0, 0}, {0, 2}, {2, 0}};
    const std::vector<double> crowding{1.0, 5.0, 3.0, 3.0};
    Rng rng(41);
    CHECK(tournament(0, 1, objectives, crowding, rng) == 0);  // dominance beats crowding
    CHECK(tournament(1, 0, objectives, crowding, rng) == 0);
    CHECK(tournament(0, 2, objectives, crowding, rng) == 2);  // incomparable: larger crowding
    // equal crowding and incomparable: a fair coin
    int first = 0;
    for (int k = 0; k < 10000; ++k) first += tournament(2, 3, objectives, crowding, rng) == 2;
    CHECK(first / 10000.0 == Approx(0.5).margin(0.025));  // 5 sd of a fair coin at n = 1e4
}

TEST_CASE("each parent enters exactly two tournaments", "[evo][selection]") {
    // a chain where i dominates everyone below it: the best wins both of its
    // tournaments (one per permutation), the worst never wins
    const std::size_t n = 40;
    Objectives objectives;
    for (std::size_t i = 0; i < n; ++i) objectives.push_back({double(i), double(i)});
    const std::vector<double> crowding(n, 1.0);
    for (std::uint64_t seed = 0; seed < 50; ++seed) {
        Rng rng(seed);
        const auto parents = select_parents(objectives, crowding, rng);
        REQUIRE(parents.size() == n);
        CHECK(std::count(parents.begin(), parents.end(), n - 1) == 2);
        CHECK(std::count(parents.begin(), parents.end(), 0) == 0);
        for (std::size_t i = 0; i < n; ++i) REQUIRE(std::count(parents.begin(), parents.end(), i) <= 2);
    }
}

TEST_CASE("selection refuses a population that is not a multiple of 4", "[evo][selection][errors]") {
    const Objectives six(6, std::vector<double>{0.0});
    const std::vector<double> crowding(6, 0.0);
    Rng rng(42);
    CHECK_THROWS_AS(select_parents(six, crowding, rng), DataError);
    CHECK_THROWS_WITH(select_parents(six, crowding, rng),
                      Equals("population size must be a positive multiple of 4, got 6"));
}

TEST_CASE("environmental selection fills whole fronts then the most spread", "[evo][selection]") {
    // front 0: {0, 1}; front 1: {2, 3, 4} with 3 interior; front 2: {5}
    const Objectives objectives{{10, 11}, {11, 10}, {0, 9}, {5, 5}, {9, 0}, {0, 0}};
    const auto kept = survivors(objectives, 4);
    CHECK(kept.indices == std::vector<std::size_t>{0, 1, 2, 4});
    CHECK(kept.rank == std::vector<std::size_t>{0, 0, 1, 1});
    CHECK(kept.crowding == std::vector<double>(4, kBoundaryCrowding));

    // a front that exactly fills the count is sorted too (sferes2 tests "<"),
    // which keeps the same set
    const auto exact = survivors(objectives, 2);
    CHECK(exact.indices == std::vector<std::size_t>{0, 1});

    // 2 + 3 = 5 is not below 5, so front 1 comes in crowding order: the
    // interior individual 3, with (9 - 0) / 9 + (9 - 0) / 9 = 2, comes last
    const auto five = survivors(objectives, 5);
    CHECK(five.indices == std::vector<std::size_t>{0, 1, 2, 4, 3});
    CHECK(five.crowding[4] == 2.0);
}

TEST_CASE("keeping more than the population is refused", "[evo][selection][errors]") {
    const Objectives two(2, std::vector<double>{0.0});
    CHECK_THROWS_WITH(survivors(two, 3), Equals("cannot keep 3 of 2 individuals"));
}
