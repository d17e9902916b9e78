// Kaplan-Meier, log-rank and permutation p against statsmodels and a full
// enumeration of relabellings: the expected values come from
// tests/stats/survival_oracle.py (statsmodels 0.13.5's SurvfuncRight and
// survdiff, itertools.combinations), pasted here.

#include "stats/survival.hpp"

#include <catch2/catch.hpp>
#include <optional>
#include <vector>

#include "core/error.hpp"

using namespace stepstone;
using namespace stepstone::stats;
using Catch::Matchers::Contains;

namespace {

struct Fixture {
    Survival a, b;
    double chi2, p;
    std::optional<double> median_a, median_b;
    std::vector<std::pair<double, double>> steps_a, steps_b;  // (event time, S after it)
};

const std::vector<Fixture>& fixtures() {
    static const std::vector<Fixture> list = {
        // ties between and within samples, censoring at event times
        {{{3, 5, 5, 8, 10, 10, 12}, {1, 1, 0, 1, 0, 1, 0}},
         {{2, 3, 3, 6, 7, 9, 11, 15}, {1, 1, 1, 0, 1, 1, 0, 1}},
         0.22077792976311267,
         0.6384478131758977,
         10.0,
         7.0,
         {{3, 0.8571428571428572},
          {5, 0.7142857142857144},
          {8, 0.5357142857142857},
          {10, 0.35714285714285726}},
         {{2, 0.875}, {3, 0.625}, {7, 0.46875}, {9, 0.31250000000000006}, {15, 0.0}}},
        // an arm with no event at all: its median is not reached
        {{{10, 10, 10, 10}, {0, 0, 0, 0}},
         {{2, 4, 6, 10}, {1, 1, 1, 0}},
         4.212648221343874,
         0.04012365005919594,
         std::nullopt,
         6.0,
         {},
         {{2, 0.75}, {4, 0.5000000000000001}, {6, 0.25000000000000006}}},
        // generations: events at 0, runs censored at the budget of 500
        {{{0, 0, 12, 40, 500, 500, 500}, {1, 1, 1, 1, 0, 0, 0}},
         {{0, 300, 500, 500, 500, 500, 500}, {1, 1, 0, 0, 0, 0, 0}},
         1.2802636631188367,
         0.25785001735768753,
         40.0,
         std::nullopt,
         {{0, 0.7142857142857144}, {12, 0.5714285714285714}, {40, 0.4285714285714286}},
         {{0, 0.8571428571428572}, {300, 0.7142857142857144}}},
    };
    return list;
}

void check_curve(const KaplanMeier& km, const std::vector<std::pair<double, double>>& expected) {
    std::vector<std::pair<double, double>> events;
    for (const auto& step : km.steps) {
        if (step.events > 0) events.emplace_back(step.time, step.survival);
    }
    REQUIRE(events.size() == expected.size());
    for (std::size_t k = 0; k < events.size(); ++k) {
        CHECK(events[k].first == expected[k].first);
        CHECK(events[k].second == Approx(expected[k].second).margin(1e-12));
    }
}

}  // namespace

TEST_CASE("log-rank chi2 and p equal statsmodels' survdiff", "[stats][survival]") {
    for (const auto& f : fixtures()) {
        const LogRank r = log_rank(f.a, f.b);
        CHECK(r.chi2 == Approx(f.chi2).epsilon(1e-9));
        CHECK(r.p == Approx(f.p).epsilon(1e-9));
        // swapping the samples changes nothing but the sides
        const LogRank s = log_rank(f.b, f.a);
        CHECK(s.chi2 == Approx(f.chi2).epsilon(1e-9));
        CHECK(s.events_a == r.events_b);
    }
}

TEST_CASE("Kaplan-Meier curves and medians equal statsmodels' SurvfuncRight", "[stats][survival]") {
    for (const auto& f : fixtures()) {
        const KaplanMeier a = kaplan_meier(f.a);
        const KaplanMeier b = kaplan_meier(f.b);
        check_curve(a, f.steps_a);
        check_curve(b, f.steps_b);
        CHECK(a.median == f.median_a);
        CHECK(b.median == f.median_b);
    }
}

TEST_CASE("Kaplan-Meier by hand: at-risk counts, censoring at an event time, S between steps",
          "[stats][survival]") {
    // times 1 (event), 2 (event), 2 (censored), 4 (event): at risk 4, 3, 1
    // S = 3/4 after 1, 3/4 * 2/3 = 1/2 after 2, 0 after 4; median: the first time S < 1/2, 4
    const KaplanMeier km = kaplan_meier({{1, 2, 2, 4}, {1, 1, 0, 1}});
    REQUIRE(km.steps.size() == 3);
    CHECK(km.steps[1].at_risk == 3);
    CHECK(km.steps[1].censored == 1);
    CHECK(km.steps[2].at_risk == 1);
    CHECK(km.at(1.5) == Approx(0.75));
    CHECK(km.at(3.0) == Approx(0.5));
    CHECK(km.at(0.5) == 1.0);
    CHECK(km.at_risk(3.0) == 1);
    CHECK(km.median == 4.0);
    CHECK(km.events == 3);
}

TEST_CASE("a log-rank test without events gives chi2 0 and p 1", "[stats][survival]") {
    const LogRank r = log_rank({{5, 5}, {0, 0}}, {{5}, {0}});
    CHECK(r.chi2 == 0.0);
    CHECK(r.p == 1.0);
}

TEST_CASE("the permutation p equals a full enumeration of the relabellings", "[stats][permutation]") {
    // by hand: a = {1, 2}, b = {0, 0}; mid-ranks 3, 4 | 1.5, 1.5; R_a = 7, mean 5. The six
    // relabellings give R = 3, 4.5, 4.5, 5.5, 5.5, 7: two are as far from 5, p = 1/3
    const std::vector<double> a1{1, 2}, b1{0, 0};
    CHECK(permutation_p(a1, b1).p == Approx(1.0 / 3.0).epsilon(1e-12));
    CHECK(permutation_p(a1, b1).exact);
    struct Case {
        std::vector<double> a, b;
        double p;
    };
    const std::vector<Case> cases = {
        {{0, 0, 1}, {0, 0, 0, 2}, 35.0 / 35.0},
        {{0, 0, 0, 0, 0, 0, 0.25, 0}, {0, 0, 0, 0, 0, 0, 0, 0, 0, 0}, 19448.0 / 43758.0},
        {{0.1, 0.4, 0.35, 0.8, 0.5}, {0.2, 0.05, 0.3, 0.3, 0.1, 0.0}, 17.0 / 462.0},
    };
    for (const auto& c : cases) {
        CHECK(permutation_p(c.a, c.b).p == Approx(c.p).epsilon(1e-12));
        CHECK(permutation_p(c.b, c.a).p == Approx(c.p).epsilon(1e-12));
    }
}

TEST_CASE("past the exact limit the permutation p is a seeded Monte Carlo with its standard error",
          "[stats][permutation]") {
    const std::vector<double> a{0.1, 0.4, 0.35, 0.8, 0.5}, b{0.2, 0.05, 0.3, 0.3, 0.1, 0.0};
    const PermutationP mc = permutation_p(a, b, /*exact_limit=*/0, /*draws=*/200000, /*seed=*/7);
    CHECK_FALSE(mc.exact);
    CHECK(mc.draws == 200000);
    // within 4 standard errors of the enumeration's 17 / 462
    CHECK(mc.standard_error > 0);
    CHECK(std::abs(mc.p - 17.0 / 462.0) < 4 * mc.standard_error);
    // the same seed, the same p
    CHECK(permutation_p(a, b, 0, 200000, 7).p == mc.p);
}

TEST_CASE("tied share and bad survival input", "[stats][survival][errors]") {
    CHECK(tied_share(std::vector<double>{0, 0, 1}, std::vector<double>{2, 3}) == Approx(0.4));
    CHECK(tied_share(std::vector<double>{1}, std::vector<double>{2}) == 0.0);
    CHECK_THROWS_AS(kaplan_meier({{}, {}}), DataError);
    CHECK_THROWS_WITH(kaplan_meier({{1, 2}, {1}}), Contains("2 times and 1 observed flags"));
    CHECK_THROWS_WITH(kaplan_meier({{1}, {2}}), Contains("not 0 or 1"));
    CHECK_THROWS_WITH(log_rank({{1}, {1}}, {{std::nan("")}, {1}}), Contains("not finite"));
    CHECK_THROWS_WITH(permutation_p(std::vector<double>{}, std::vector<double>{1}), Contains("empty"));
}
