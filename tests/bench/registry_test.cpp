#include <catch2/catch.hpp>

#include <stdexcept>

#include "bench/registry.hpp"
#include "bench/runner.hpp"

using namespace stepstone::bench;

namespace {

Case counting_case(const std::string& name, int* baseline_calls, int* candidate_calls) {
    Case c;
    c.name = name;
    c.unit = "units";
    c.target_ratio = 2;
    c.make = [=](Size) {
        return Workload{[=] {
                            ++*baseline_calls;
                            return std::uint64_t{1};
                        },
                        [=] {
                            ++*candidate_calls;
                            return std::uint64_t{3};
                        }};
    };
    return c;
}

}  // namespace

TEST_CASE("the registry finds cases by name and refuses duplicates", "[bench][registry]") {
    int a = 0;
    int b = 0;
    Registry registry;
    registry.add(counting_case("one", &a, &b));
    registry.add(counting_case("two", &a, &b));
    CHECK(registry.find("two") != nullptr);
    CHECK(registry.find("three") == nullptr);
    CHECK(registry.names() == std::vector<std::string>{"one", "two"});
    CHECK_THROWS_AS(registry.add(counting_case("one", &a, &b)), std::invalid_argument);
    CHECK_THROWS_AS(registry.add(counting_case("", &a, &b)), std::invalid_argument);
}

TEST_CASE("the runner calls both sides in every round and reports their ratio", "[bench][registry]") {
    int baseline_calls = 0;
    int candidate_calls = 0;
    const Case c = counting_case("count", &baseline_calls, &candidate_calls);
    RunOptions options;
    options.repetitions = 3;
    options.min_seconds = 0;
    int rounds_seen = 0;
    const auto result = run_case(c, options, [&](int done, int total) {
        CHECK(total == 3);
        rounds_seen = done;
    });
    CHECK(rounds_seen == 3);
    // one warm-up call plus at least one call per round
    CHECK(baseline_calls >= 4);
    CHECK(candidate_calls >= 4);
    CHECK(result.name == "count");
    CHECK(result.baseline_per_s > 0);
    CHECK(result.candidate_per_s > 0);
    CHECK(result.ratio == result.candidate_per_s / result.baseline_per_s);
    CHECK(result.target_ratio == 2);
}

TEST_CASE("a side that does no work is reported, not divided by", "[bench][registry]") {
    Case c;
    c.name = "idle";
    c.make = [](Size) { return Workload{[] { return std::uint64_t{0}; }, [] { return std::uint64_t{1}; }}; };
    CHECK_THROWS_AS(run_case(c, quick_options()), std::logic_error);
}
