#include <catch2/catch.hpp>

#include <algorithm>
#include <vector>

#include "core/rng.hpp"
#include "evo/pareto.hpp"

using namespace stepstone;
using namespace stepstone::evo;

namespace {

// brute-force oracle: peel the set of individuals no remaining one dominates
std::vector<std::vector<std::size_t>> fronts_by_peeling(const Objectives& objectives) {
    std::vector<std::size_t> remaining(objectives.size());
    for (std::size_t i = 0; i < remaining.size(); ++i) remaining[i] = i;
    std::vector<std::vector<std::size_t>> fronts;
    while (!remaining.empty()) {
        std::vector<std::size_t> front, rest;
        for (std::size_t p : remaining) {
            bool dominated = false;
            for (std::size_t q : remaining) {
                // q dominates p: >= everywhere, > somewhere (maximisation), written out here
                bool ge = true, gt = false;
                for (std::size_t m = 0; m < objectives[p].size(); ++m) {
                    ge = ge && objectives[q][m] >= objectives[p][m];
                    gt = gt || objectives[q][m] > objectives[p][m];
                }
                dominated = dominated || (ge && gt);
            }
            (dominated ? rest : front).push_back(p);
        }
        fronts.push_back(front);
        remaining = rest;
    }
    return fronts;
}

Objectives random_objectives(Rng& rng, std::size_t n, std::size_t m, std::uint64_t levels) {
    Objectives objectives(n, std::vector<double>(m));
    for (auto& row : objectives) {
        for (auto& x : row) x = static_cast<double>(rng.below(levels));  // few levels: many ties
    }
    return objectives;
}

}  // namespace

TEST_CASE("dominance is for maximisation and strict somewhere", "[evo][pareto]") {
    const std::vector<double> a{2, 3}, b{1, 3}, c{2, 3}, d{3, 1};
    CHECK(dominates(a, b));
    CHECK_FALSE(dominates(b, a));
    CHECK_FALSE(dominates(a, c));  // equal vectors do not dominate each other
    CHECK_FALSE(dominates(a, d));
    CHECK_FALSE(dominates(d, a));
}

TEST_CASE("fast non-dominated sort finds the fronts of the brute-force oracle", "[evo][pareto]") {
    Rng rng(31);
    for (int trial = 0; trial < 300; ++trial) {
        const std::size_t n = 1 + rng.below(60);
        const std::size_t m = 1 + rng.below(3);
        const auto objectives = random_objectives(rng, n, m, 2 + rng.below(10));
        REQUIRE(non_dominated_fronts(objectives) == fronts_by_peeling(objectives));
    }
}

TEST_CASE("crowding distance matches a hand-computed front", "[evo][pareto]") {
    // sorted by f0: A(0) B(1) C(3) D(4), range 4: B += 3/4, C += 3/4;
    // sorted by f1: D(0) C(3) B(6) A(10), range 10: C += 6/10, B += 7/10; ends 1e14
    const Objectives objectives{{0, 10}, {1, 6}, {3, 3}, {4, 0}};
    const std::vector<std::size_t> front{0, 1, 2, 3};
    const auto d = crowding_distance(objectives, front);
    CHECK(d[0] == kBoundaryCrowding);
    CHECK(d[1] == Approx(1.45));
    CHECK(d[2] == Approx(1.35));
    CHECK(d[3] == kBoundaryCrowding);
}

TEST_CASE("crowding sets the boundaries of each objective and adds the rest", "[evo][pareto]") {
    // P1 is interior for f0 and f1 (1 + 1) but an end for f2, so it is set to 1e14;
    // P0 is an end for f1 and interior for f2, so it gets 1e14 + (2 - 0) / 2
    const Objectives objectives{{0, 2, 1}, {1, 1, 2}, {2, 0, 0}};
    const std::vector<std::size_t> front{0, 1, 2};
    const auto d = crowding_distance(objectives, front);
    CHECK(d[0] == kBoundaryCrowding + 1.0);
    CHECK(d[1] == kBoundaryCrowding);
    CHECK(d[2] == kBoundaryCrowding);
}

TEST_CASE("fronts of one or two are all boundary, a flat objective adds nothing", "[evo][pareto]") {
    const Objectives objectives{{0, 5}, {1, 5}, {2, 5}};
    const std::vector<std::size_t> one{1}, two{0, 2}, three{0, 1, 2};
    CHECK(crowding_distance(objectives, one) == std::vector<double>{kBoundaryCrowding});
    CHECK(crowding_distance(objectives, two) == std::vector<double>(2, kBoundaryCrowding));
    // f0: middle gets (2 - 0) / 2 = 1; f1 has range 0
    CHECK(crowding_distance(objectives, three) == std::vector<double>{kBoundaryCrowding, 1.0, kBoundaryCrowding});
}

TEST_CASE("rank_and_crowd gives each individual its front and crowding", "[evo][pareto]") {
    Rng rng(32);
    const auto objectives = random_objectives(rng, 50, 2, 8);
    const auto ranking = rank_and_crowd(objectives);
    for (std::size_t r = 0; r < ranking.fronts.size(); ++r) {
        const auto crowding = crowding_distance(objectives, ranking.fronts[r]);
        for (std::size_t k = 0; k < ranking.fronts[r].size(); ++k) {
            CHECK(ranking.rank[ranking.fronts[r][k]] == r);
            CHECK(ranking.crowding[ranking.fronts[r][k]] == crowding[k]);
        }
    }
}
