#include "kb/calibrate.hpp"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <tuple>
#include <vector>

#include "core/error.hpp"
#include "core/rng.hpp"

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

namespace {

// the windows of `width` rows at stride 1 of a (steps x channels) behaviour, materialised
std::vector<float> materialise_windows(const std::vector<float>& behaviour, std::size_t channels,
                                       std::size_t width) {
    const std::size_t steps = behaviour.size() / channels;
    std::vector<float> out;
    for (std::size_t i = 0; i + width <= steps; ++i)
        out.insert(out.end(), behaviour.begin() + i * channels, behaviour.begin() + (i + width) * channels);
    return out;
}

// the excluding variant by brute force: each window's k nearest among the
// windows at least `width` away, distances from the materialised windows
double brute_excluding(const std::vector<float>& windows, std::size_t dim, std::size_t width, std::size_t k) {
    const std::size_t n = windows.size() / dim;
    double total = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        std::vector<double> d;
        for (std::size_t j = 0; j < n; ++j) {
            if ((i > j ? i - j : j - i) < width) continue;
            double s = 0.0;
            for (std::size_t v = 0; v < dim; ++v) {
                const double x = static_cast<double>(windows[i * dim + v]) - windows[j * dim + v];
                s += x * x;
            }
            d.push_back(std::sqrt(s));
        }
        std::sort(d.begin(), d.end());
        const std::size_t m = std::min(k, d.size());
        double sum = 0.0;
        for (std::size_t q = 0; q < m; ++q) sum += d[q];
        total += sum / static_cast<double>(m);
    }
    return total / static_cast<double>(n);
}

}  // namespace

TEST_CASE("the windows reading equals the rule applied to every window, with and without overlaps",
          "[kb][calibrate][windows]") {
    // oracles: the segments reading (calibrate_delta) over the materialised
    // windows is the including variant; a brute force over the windows at
    // least a width apart is the excluding one
    Rng rng(7, 0, 0, Purpose::test);
    for (const auto& [steps, channels, width, k] :
         {std::tuple<std::size_t, std::size_t, std::size_t, std::size_t>{90, 3, 5, 4},
          {61, 2, 7, 20},
          {40, 15, 3, 1}}) {
        CAPTURE(steps, channels, width, k);
        std::vector<float> behaviour(steps * channels);
        for (float& v : behaviour) v = rng.below(3) == 0 ? 1.0f : static_cast<float>(rng.uniform());
        const auto windows = materialise_windows(behaviour, channels, width);
        const std::size_t dim = width * channels;
        const auto got = kb::calibrate_delta_windows(behaviour, channels, width, k);
        CHECK(got.windows == steps - width + 1);
        CHECK(got.including_overlap ==
              Approx(kb::calibrate_delta(kb::Segments{windows, dim}, k)).epsilon(1e-9));
        CHECK(got.excluding_overlap == Approx(brute_excluding(windows, dim, width, k)).epsilon(1e-9));
        // every window's candidates without overlaps are a subset of those with them
        CHECK(got.including_overlap <= got.excluding_overlap);
    }
}

TEST_CASE("the windows reading refuses behaviours too short for a window apart", "[kb][calibrate][errors]") {
    const std::vector<float> short_walk(2 * 20 * 3, 0.5f);  // 40 steps of 3 channels, width 20: 59 needed
    REQUIRE_THROWS_AS(kb::calibrate_delta_windows(short_walk, 3, 20), DataError);
    REQUIRE_THROWS_WITH(kb::calibrate_delta_windows(short_walk, 3, 20), Contains("at least 59 steps"));
    const std::vector<float> enough(59 * 3, 0.5f);
    CHECK(kb::calibrate_delta_windows(enough, 3, 20).excluding_overlap == 0.0);
    const std::vector<float> ragged(10, 0.0f);
    REQUIRE_THROWS_WITH(kb::calibrate_delta_windows(ragged, 3, 1), Contains("not rows of 3"));
}
