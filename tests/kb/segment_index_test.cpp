#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "core/error.hpp"
#include "core/rng.hpp"
#include "kb/distance.hpp"
#include "kb/segment_index.hpp"
#include "oracle.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;

namespace {

// the nearest with squared distance < r^2, by linear scan (ties: lowest id)
std::optional<std::pair<std::size_t, double>> oracle_within(const std::vector<float>& values, std::size_t dim,
                                                            const float* q, double r) {
    auto best = kbtest::oracle_nearest(values, dim, q);
    if (best && best->second < r * r) return best;
    return std::nullopt;
}

void check_queries(kb::SegmentIndex& index, const std::vector<float>& values, const std::vector<float>& queries,
                   double radius) {
    const std::size_t dim = index.dim();
    for (std::size_t i = 0; i * dim < queries.size(); ++i) {
        const float* q = queries.data() + i * dim;
        const auto expect = oracle_within(values, dim, q, radius);
        const auto got = index.nearest_within(values, q, radius);
        const auto got_adaptive = index.nearest_within_adaptive(values, q, radius);
        REQUIRE(got.has_value() == expect.has_value());
        REQUIRE(got_adaptive.has_value() == expect.has_value());
        if (expect) {
            REQUIRE(got->id == expect->first);
            REQUIRE(got->squared_distance == expect->second);
            REQUIRE(got_adaptive->id == expect->first);
        }
        const auto nearest = index.nearest(values, q);
        const auto expect_nearest = kbtest::oracle_nearest(values, dim, q);
        REQUIRE(nearest.has_value() == expect_nearest.has_value());
        if (expect_nearest) {
            REQUIRE(nearest->id == expect_nearest->first);
            REQUIRE(nearest->squared_distance == expect_nearest->second);
        }
    }
}

}  // namespace

TEST_CASE("the distance follows the documented lane order", "[kb][distance]") {
    // the oracle writes the documented order as a plain loop
    Rng rng(3, 0, 0, Purpose::test);
    for (std::size_t dim : {1u, 2u, 7u, 8u, 9u, 31u, 32u, 33u, 300u}) {
        const std::vector<float> v = kbtest::uniform_segments(rng, 2, dim);
        const double expect = kbtest::oracle_squared_distance(v.data(), v.data() + dim, dim);
        CHECK(kb::squared_distance(v.data(), v.data() + dim, dim) == expect);
        // with a bound above the distance the value is exact, below it the result exceeds the bound
        CHECK(kb::squared_distance_up_to(v.data(), v.data() + dim, dim, expect) == expect);
        CHECK(kb::squared_distance_up_to(v.data(), v.data() + dim, dim, expect * 0.5) > expect * 0.5);
    }
    // by hand: (0,0,0) to (1,2,2) is 9
    const float a[3] = {0, 0, 0}, b[3] = {1, 2, 2};
    CHECK(kb::squared_distance(a, b, 3) == 9.0);
}

TEST_CASE("the index equals a linear scan after many inserts and rebuilds", "[kb][index]") {
    // clustered data prunes well (tree path), uniform data in 300-D does not
    // (brute-force path); both must give the linear scan's answers
    struct Setup {
        std::size_t width, channels;
        int kind;
        double radius;
    };
    const Setup setups[] = {{1, 2, 1, 0.3}, {5, 3, 1, 1.0}, {20, 15, 1, 2.5}, {20, 15, 0, 7.0}, {4, 3, 2, 0.5}};
    for (const Setup s : setups) {
        const std::size_t dim = s.width * s.channels;
        CAPTURE(dim, s.kind);
        Rng rng(41, dim, static_cast<std::uint64_t>(s.kind), Purpose::test);
        const std::size_t n = dim >= 300 ? 1500 : 3000;
        const std::vector<float> data = s.kind == 0   ? kbtest::uniform_segments(rng, n, dim)
                                        : s.kind == 1 ? kbtest::clustered_segments(rng, n, dim, 30, 0.2)
                                                      : kbtest::grid_segments(rng, n, dim, 3);
        kb::SegmentIndex index(s.width, s.channels);
        std::vector<float> values;
        const std::vector<float> queries = s.kind == 0   ? kbtest::uniform_segments(rng, 12, dim)
                                           : s.kind == 1 ? kbtest::clustered_segments(rng, 12, dim, 30, 0.3)
                                                         : kbtest::grid_segments(rng, 12, dim, 3);
        for (std::size_t i = 0; i < n; ++i) {
            values.insert(values.end(), data.begin() + static_cast<std::ptrdiff_t>(i * dim),
                          data.begin() + static_cast<std::ptrdiff_t>((i + 1) * dim));
            index.append(values.data() + i * dim);
            // check around buffer flushes and at irregular sizes
            if (i % 97 == 0 || i % 64 == 63 || i % 64 == 0) check_queries(index, values, queries, s.radius);
        }
        CHECK(index.size() == n);
        CHECK(index.stats().rebuilds > 5);
        // a bulk-built index gives the same answers
        kb::SegmentIndex bulk(s.width, s.channels);
        bulk.assign(values);
        check_queries(bulk, values, queries, s.radius);
        // existing segments as queries: distance 0, lowest id among duplicates
        check_queries(index, values, std::vector<float>(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(20 * dim)), s.radius);
    }
}

TEST_CASE("the index falls back to brute force when the lower bounds prune nothing", "[kb][index]") {
    // uniform values in 300-D: channel means all lie near 1/2, so most of the
    // KB passes the lower bound for a radius of 7 (typical distances ~7)
    Rng rng(8, 0, 0, Purpose::test);
    const std::size_t dim = 300;
    const std::vector<float> values = kbtest::uniform_segments(rng, 800, dim);
    kb::SegmentIndex index(20, 15);
    index.assign(values);
    const std::vector<float> queries = kbtest::uniform_segments(rng, 200, dim);
    for (std::size_t i = 0; i < 200; ++i) index.nearest_within_adaptive(values, queries.data() + i * dim, 7.0);
    CHECK(index.brute_force());
    CHECK(index.stats().linear_queries > 0);
    // clustered data with a small radius stays on the trees
    const std::vector<float> clustered = kbtest::clustered_segments(rng, 800, dim, 40, 0.05);
    kb::SegmentIndex tree(20, 15);
    tree.assign(clustered);
    for (std::size_t i = 0; i < 200; ++i) tree.nearest_within_adaptive(clustered, clustered.data() + i * dim, 1.0);
    CHECK_FALSE(tree.brute_force());
    CHECK(tree.stats().linear_queries == 0);
}

TEST_CASE("an index needs a width and channels", "[kb][index][errors]") {
    REQUIRE_THROWS_WITH(kb::SegmentIndex(0, 3), Contains("segment_width must be >= 1, got 0"));
    REQUIRE_THROWS_WITH(kb::SegmentIndex(3, 0), Contains("channels must be >= 1, got 0"));
    kb::SegmentIndex empty(2, 2);
    const float q[4] = {0, 0, 0, 0};
    CHECK_FALSE(empty.nearest({}, q).has_value());
    CHECK_FALSE(empty.nearest_within({}, q, 1.0).has_value());
}
