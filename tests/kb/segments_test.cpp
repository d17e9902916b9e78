#include <catch2/catch.hpp>

#include <numeric>
#include <vector>

#include "core/error.hpp"
#include "kb/segments.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;

TEST_CASE("a behaviour is cut into whole windows of rows and a trailing partial window is dropped", "[kb][segments]") {
    // 7 steps x 2 channels, values 0..13 row by row; width 3 gives windows of
    // rows {0,1,2} and {3,4,5}; row 6 (values 12, 13) is a partial window
    std::vector<float> behaviour(14);
    std::iota(behaviour.begin(), behaviour.end(), 0.0f);
    const kb::Segments s = kb::segment_behaviour(behaviour, 2, 3);
    REQUIRE(s.dim == 6);
    REQUIRE(s.size() == 2);
    CHECK(std::vector<float>(s[0].begin(), s[0].end()) == std::vector<float>{0, 1, 2, 3, 4, 5});
    CHECK(std::vector<float>(s[1].begin(), s[1].end()) == std::vector<float>{6, 7, 8, 9, 10, 11});
    CHECK(s.values.size() == 12);
}

TEST_CASE("the paper's behaviour of 4000 steps of 15 channels gives 200 segments of 300 values", "[kb][segments]") {
    // section III.E: w = 20, T = 4000, ns + ne = 15
    std::vector<float> behaviour(4000 * 15, 0.5f);
    const kb::Segments s = kb::segment_behaviour(behaviour, 15, 20);
    CHECK(s.size() == 200);
    CHECK(s.dim == 300);
    // 4010 / 20 = 200.5: the half window is dropped
    CHECK(kb::segment_count(4010, 20) == 200);
    CHECK(kb::segment_count(19, 20) == 0);
}

TEST_CASE("a behaviour that is not a whole number of rows is refused", "[kb][segments][errors]") {
    std::vector<float> behaviour(7);
    REQUIRE_THROWS_AS(kb::segment_behaviour(behaviour, 2, 3), DataError);
    REQUIRE_THROWS_WITH(kb::segment_behaviour(behaviour, 2, 3), Contains("7 values") && Contains("2 channels"));
    REQUIRE_THROWS_WITH(kb::segment_behaviour(behaviour, 0, 3), Contains("channels must be >= 1, got 0"));
    REQUIRE_THROWS_WITH(kb::segment_behaviour(behaviour, 7, 0), Contains("segment_width must be >= 1, got 0"));
    REQUIRE_THROWS_WITH(kb::as_segments(behaviour, 3), Contains("not a whole number of segments of 3"));
}
