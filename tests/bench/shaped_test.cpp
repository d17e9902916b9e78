#include <catch2/catch.hpp>

#include "bench/bench_shaped.hpp"
#include "support/run_cli.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;

TEST_CASE("the shaped cases' KB has the structure of a source run's", "[bench][shaped]") {
    // a paper-size source run's KB at 1.83 (docs/results.md section 9):
    // 149,233 segments, 19,022 of them (12.7 %) averaging more than 0; the
    // fixture's 500 policies (15 % rewarded, as in that run) must give a KB
    // of the same kind, mostly zero averages, and a smaller one at 3.84
    const auto fine = bench::shaped_kb_shape(bench::Size::full, 1.83);
    const auto coarse = bench::shaped_kb_shape(bench::Size::full, 3.84);
    INFO(fine.segments << " segments, " << fine.positive << " positive; at 3.84 " << coarse.segments);
    CHECK(fine.segments > 10000);
    const double share = static_cast<double>(fine.positive) / static_cast<double>(fine.segments);
    CHECK(share > 0.05);
    CHECK(share < 0.3);
    CHECK(coarse.segments < fine.segments / 3);
    CHECK(coarse.positive > 0);
}

TEST_CASE("bench runs both shaped cases and reports a ratio for each", "[bench][shaped][cli]") {
    auto result = test::run_cli({"bench", "shaped-1.83", "shaped-3.84", "--quick", "--csv"});
    INFO(result.out << result.err);
    CHECK(result.exit_code == 0);
    CHECK_THAT(result.out, Contains("\nshaped-1.83,") && Contains("\nshaped-3.84,"));
    CHECK_THAT(result.out, !Contains(",,,"));
}
