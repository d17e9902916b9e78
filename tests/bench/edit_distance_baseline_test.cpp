#include "reference/edit_distance_baseline.hpp"

#include <catch2/catch.hpp>
#include <vector>

using namespace stepstone::reference;

TEST_CASE("the baseline edit distance follows the original's costs", "[bench][diversity]") {
    using Cells = std::vector<GridCell>;
    const Cells a{{0, 0}, {1, 0}, {2, 1}};
    // identical sequences
    CHECK(edit_distance_baseline(a, a) == 0.0f);
    // one deletion costs 1
    CHECK(edit_distance_baseline(Cells{{0, 0}, {1, 0}}, Cells{{0, 0}}) == 1.0f);
    // against an empty sequence: one insertion per cell
    CHECK(edit_distance_baseline(Cells{}, a) == 3.0f);
    // substitution costs the Manhattan distance / 12: (0,0) vs (3,0) -> 3 / 12
    CHECK(edit_distance_baseline(Cells{{0, 0}}, Cells{{3, 0}}) == Approx(0.25));
    // (0,0)(1,0) vs (1,0)(0,0): two substitutions would cost 2 / 12; the
    // transposition costs table[0][0] + cost((1,0), (0,0)) = 1 / 12
    CHECK(edit_distance_baseline(Cells{{0, 0}, {1, 0}}, Cells{{1, 0}, {0, 0}}) == Approx(1.0 / 12));
    // far cells: substitution (30 / 12 = 2.5) loses to delete + insert (2)
    CHECK(edit_distance_baseline(Cells{{0, 0}}, Cells{{20, 10}}) == 2.0f);
}

TEST_CASE("the baseline diversity sums every pair's distance once per side", "[bench][diversity]") {
    // distances: t0-t1 = 1 / 12, t0-t2 = 2 / 12, t1-t2 = 1 / 12 (one cell each)
    const std::vector<std::vector<GridCell>> t{{{0, 0}}, {{1, 0}}, {{2, 0}}};
    const auto sums = diversity_baseline(t);
    REQUIRE(sums.size() == 3);
    CHECK(sums[0] == Approx(3.0 / 12));
    CHECK(sums[1] == Approx(2.0 / 12));
    CHECK(sums[2] == Approx(3.0 / 12));
}

TEST_CASE("random trajectories stay on the reachable board and move by at most one cell", "[bench][diversity]") {
    const auto t = random_trajectories(20, 80, 3);
    REQUIRE(t.size() == 20);
    for (const auto& trajectory : t) {
        REQUIRE(trajectory.size() == 80);
        for (std::size_t k = 0; k < trajectory.size(); ++k) {
            CHECK(trajectory[k].x >= 0);
            CHECK(trajectory[k].x < 12);
            CHECK(trajectory[k].y >= 0);
            CHECK(trajectory[k].y < 8);
            if (k > 0) {
                CHECK(std::abs(trajectory[k].x - trajectory[k - 1].x) + std::abs(trajectory[k].y - trajectory[k - 1].y) <= 1);
            }
        }
    }
}
