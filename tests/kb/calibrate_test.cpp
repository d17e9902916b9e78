#include <catch2/catch.hpp>

#include <vector>

#include "core/error.hpp"
#include "kb/calibrate.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;

TEST_CASE("delta is the mean over segments of the mean distance to their nearest others", "[kb][calibrate]") {
    // by hand, 1-D segments at 0, 1, 3:
    // one neighbour: 0 -> 1, 1 -> 1, 3 -> 2; mean 4/3
    // two neighbours: 0 -> (1 + 3)/2 = 2, 1 -> (1 + 2)/2 = 1.5, 3 -> (3 + 2)/2 = 2.5; mean 2
    // twenty neighbours with only two others: same as two
    const std::vector<float> policy{0, 1, 3};
    const kb::Segments s{policy, 1};
    CHECK(kb::calibrate_delta(s, 1) == Approx(4.0 / 3.0));
    CHECK(kb::calibrate_delta(s, 2) == Approx(2.0));
    CHECK(kb::calibrate_delta(s) == Approx(2.0));
    // 2-D: (0,0), (3,4): each other's only neighbour at 5
    const std::vector<float> two{0, 0, 3, 4};
    CHECK(kb::calibrate_delta(kb::Segments{two, 2}) == Approx(5.0));
}

TEST_CASE("calibration refuses policies with fewer than two segments", "[kb][calibrate][errors]") {
    const std::vector<float> one{0};
    REQUIRE_THROWS_AS(kb::calibrate_delta(kb::Segments{one, 1}), DataError);
    REQUIRE_THROWS_WITH(kb::calibrate_delta(kb::Segments{one, 1}), Contains("1 segment"));
    const std::vector<float> policy{0, 1};
    REQUIRE_THROWS_WITH(kb::calibrate_delta(kb::Segments{policy, 1}, 0), Contains("neighbours must be >= 1"));
}

TEST_CASE("KB sizes for several deltas follow the observe rule", "[kb][calibrate]") {
    // by hand, 1-D policy {0, 1, 3}:
    // delta 0.5: nothing matches, 3 segments
    // delta 1.5: 1 matches 0; 3 is 3 from 0: 2 segments
    // delta 10: everything matches 0: 1 segment
    // a second identical policy adds nothing
    const std::vector<float> policy{0, 1, 3};
    const std::vector<kb::Segments> policies{kb::Segments{policy, 1}, kb::Segments{policy, 1}};
    kb::KbParams p;
    p.segment_width = 1;
    p.channels = 1;
    const std::vector<double> deltas{0.5, 1.5, 10};
    const auto sizes = kb::kb_sizes(p, policies, deltas);
    REQUIRE(sizes.size() == 3);
    CHECK(sizes[0].delta == 0.5);
    CHECK(sizes[0].size == 3);
    CHECK(sizes[1].size == 2);
    CHECK(sizes[2].size == 1);
    const std::vector<double> bad{-1};
    REQUIRE_THROWS_WITH(kb::kb_sizes(p, policies, bad), Contains("delta must be > 0"));
}
