// The FLANN baseline of `kb-flann` answers the same queries as the exact
// index: its neighbours are approximate, so only their quality is bounded.

#include <catch2/catch.hpp>

#include "bench/bench_kb.hpp"

using namespace stepstone;

TEST_CASE("kb-flann: FLANN's kd-forest finds most exact nearest neighbours of the quick workload",
          "[bench][kb]") {
    const bench::KbFlannMeasurements m = bench::measure_kb_flann(bench::Size::quick);
    CHECK(m.kb_size == 4000);
    CHECK(m.queries == 4000);
    // approximate: recall below 1 is expected, a broken wiring would read ~0
    CHECK(m.recall > 0.5);
    CHECK(m.recall <= 1.0);
    // every query FLANN answers exactly gets the right within-delta match
    CHECK(m.match_agreement >= m.recall);
    CHECK(m.within_delta > 0.0);
    CHECK(m.lookup_queries_per_s > 0.0);
    CHECK(m.flann_queries_per_s > 0.0);
}
