// The five treatments: their names, the objectives each selects on, and the
// sum objective's ranking guarantee, checked by hand and over random draws.
// How runs apply them is tested in tests/exp/evolution_test.cpp.
#include "runs/treatment.hpp"

#include <catch2/catch.hpp>
#include <random>

using namespace stepstone;
using Catch::Matchers::Contains;

namespace {

constexpr double kBall = 1.0 / 24.0;  // one ball of 24 (8 balls x 3 starts)

// how a refused seeded name points to its shaping: "with treatment sum"
std::string concat_name(runs::Treatment plain) {
    return "with treatment " + std::string(runs::to_string(plain));
}

}  // namespace

TEST_CASE("sum fitness: n balls always rank below n + 1 balls whatever the shaping", "[runs][treatment]") {
    std::mt19937_64 random(2024);
    std::uniform_int_distribution<int> balls(0, 23);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (int trial = 0; trial < 200000; ++trial) {
        const int n = balls(random);
        const double max_average = 1e-3 + unit(random);
        // the worst case for the guarantee: n balls with the largest r_max, n + 1 with none
        const double high = (trial % 3 == 0) ? max_average : unit(random) * max_average;
        const double low = (trial % 3 == 0) ? 0.0 : unit(random) * max_average;
        const double with_n = runs::sum_fitness(n * kBall, high, max_average, kBall);
        const double with_more = runs::sum_fitness((n + 1) * kBall, low, max_average, kBall);
        REQUIRE(with_n < with_more);
    }
}

TEST_CASE("sum fitness by hand: the normalised r_max times one ball less the margin", "[runs][treatment]") {
    // 2 balls, r_max 0.3 of a KB whose best average is 0.6: 2/24 + 0.5 x (1/24) x (1 - 1/1024)
    CHECK(runs::sum_fitness(2 * kBall, 0.3, 0.6, kBall) ==
          Approx(2.0 / 24 + 0.5 / 24 * 1023.0 / 1024).epsilon(1e-15));
    // r_max = 0 adds nothing; a KB whose averages are all 0 shapes nothing
    CHECK(runs::sum_fitness(3 * kBall, 0.0, 0.6, kBall) == 3 * kBall);
    CHECK(runs::sum_fitness(3 * kBall, 0.0, 0.0, kBall) == 3 * kBall);
    // more r_max, more fitness at equal reward
    CHECK(runs::sum_fitness(kBall, 0.2, 0.6, kBall) < runs::sum_fitness(kBall, 0.4, 0.6, kBall));
}

TEST_CASE("each treatment selects on its own objectives", "[runs][treatment]") {
    using runs::Treatment;
    const double r = 5 * kBall, d = 17.0, rmax = 0.25, top = 0.5;
    CHECK(runs::treatment_objectives(Treatment::none, r, d, std::nullopt, 0, kBall) ==
          std::vector<double>{r, d});
    CHECK(runs::treatment_objectives(Treatment::none, r, d, rmax, top, kBall) == std::vector<double>{r, d});
    const double shaped = r + 0.5 * kBall * (1.0 - 1.0 / 1024);
    for (Treatment t : {Treatment::sum, Treatment::sum_rand}) {
        const auto o = runs::treatment_objectives(t, r, d, rmax, top, kBall);
        REQUIRE(o.size() == 2);
        CHECK(o[0] == Approx(shaped).epsilon(1e-15));
        CHECK(o[1] == d);
    }
    for (Treatment t : {Treatment::mo, Treatment::mo_rand}) {
        CHECK(runs::treatment_objectives(t, r, d, rmax, top, kBall) == std::vector<double>{r, d, rmax});
    }
}

TEST_CASE("treatment names parse and print, and an unknown one is refused", "[runs][treatment]") {
    for (auto t : runs::all_treatments()) CHECK(runs::parse_treatment(std::string(runs::to_string(t))) == t);
    CHECK(runs::all_treatments().size() == 5);
    CHECK_THROWS_WITH(
        runs::parse_treatment("summ", "--treatment"),
        Contains("--treatment") && Contains("none, sum, mo, sum-rand, mo-rand") && Contains("summ"));
}

TEST_CASE("seeded treatments: their names, their shaping and their twins", "[runs][treatment][seed]") {
    using runs::Treatment;
    const std::vector<std::pair<Treatment, Treatment>> twins = {
        {Treatment::none, Treatment::seed},
        {Treatment::sum, Treatment::seed_sum},
        {Treatment::mo, Treatment::seed_mo},
        {Treatment::sum_rand, Treatment::seed_sum_rand},
        {Treatment::mo_rand, Treatment::seed_mo_rand}};
    for (const auto& [plain, seeded] : twins) {
        INFO(runs::to_string(seeded));
        CHECK(
            runs::to_string(seeded) ==
            (plain == Treatment::none ? std::string("seed") : "seed-" + std::string(runs::to_string(plain))));
        CHECK(runs::parse_treatment(std::string(runs::to_string(seeded))) == seeded);
        CHECK(runs::is_seeded(seeded));
        CHECK_FALSE(runs::is_seeded(plain));
        CHECK(runs::shaping_of(seeded) == plain);
        CHECK(runs::shaping_of(plain) == plain);
        CHECK(runs::seeded(plain) == seeded);
        CHECK(runs::seeded(seeded) == seeded);
        // a seeded treatment shapes as its twin does
        CHECK(runs::needs_kb(seeded) == runs::needs_kb(plain));
        CHECK(runs::needs_randomized_kb(seeded) == runs::needs_randomized_kb(plain));
        CHECK(runs::adds_shaping(seeded) == runs::adds_shaping(plain));
        CHECK(runs::shaping_objective(seeded) == runs::shaping_objective(plain));
        CHECK(runs::treatment_objectives(seeded, 0.25, 3.0, 0.5, 1.0, kBall) ==
              runs::treatment_objectives(plain, 0.25, 3.0, 0.5, 1.0, kBall));
        // a run config names the shaping alone
        CHECK(runs::parse_shaping_treatment(std::string(runs::to_string(plain))) == plain);
        CHECK_THROWS_WITH(runs::parse_shaping_treatment(std::string(runs::to_string(seeded)), "t.treatment"),
                          Contains("t.treatment must be one of none, sum, mo, sum-rand, mo-rand") &&
                              Contains(concat_name(plain)));
    }
    // the campaign default stays the paper's five
    for (auto t : runs::all_treatments()) CHECK_FALSE(runs::is_seeded(t));
}
