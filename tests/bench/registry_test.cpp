#include "bench/registry.hpp"

#include <catch2/catch.hpp>
#include <chrono>
#include <initializer_list>
#include <memory>
#include <stdexcept>
#include <thread>
#include <utility>
#include <vector>

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

// a registry of counting cases of these names
Registry registry_of(std::initializer_list<std::string> names, int* calls) {
    Registry registry;
    for (const auto& name : names) registry.add(counting_case(name, calls, calls));
    return registry;
}

}  // namespace

TEST_CASE("the registry finds cases by name and refuses duplicates", "[bench][registry]") {
    int a = 0;
    int b = 0;
    Registry registry = registry_of({"one", "two"}, &a);
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
    REQUIRE(result.baseline_rates.size() == 3);
    REQUIRE(result.candidate_rates.size() == 3);
    CHECK(result.ratio == paired_ratio(result.baseline_rates, result.candidate_rates).median);
    CHECK(result.ratio_min <= result.ratio);
    CHECK(result.ratio <= result.ratio_max);
    CHECK(result.target_ratio == 2);
}

TEST_CASE("the paired ratio is the median of the rounds' own ratios, not the ratio of the medians",
          "[bench][registry]") {
    // rounds' ratios 400/100 = 4, 200/200 = 1, 400/400 = 1: median 1; the ratio of the
    // medians would be 400 / 200 = 2
    const std::vector<double> baseline{100, 200, 400};
    const std::vector<double> candidate{400, 200, 400};
    auto paired = paired_ratio(baseline, candidate);
    CHECK(paired.median == 1.0);
    CHECK(paired.min == 1.0);
    CHECK(paired.max == 4.0);

    // four rounds: ratios 3, 2, 1, 2, sorted 1 2 2 3, median (2 + 2) / 2 = 2; the ratio of the
    // medians would be 300 / 200 = 1.5
    paired = paired_ratio(std::vector<double>{100, 100, 300, 300}, std::vector<double>{300, 200, 300, 600});
    CHECK(paired.median == 2.0);
    CHECK(paired.min == 1.0);
    CHECK(paired.max == 3.0);

    // an even count whose middle ratios differ: 1, 1.5, 2.5, 4 -> (1.5 + 2.5) / 2 = 2
    paired = paired_ratio(std::vector<double>{10, 10, 10, 10}, std::vector<double>{40, 15, 10, 25});
    CHECK(paired.median == 2.0);

    CHECK_THROWS_AS(paired_ratio(std::vector<double>{1, 2}, std::vector<double>{1}), std::invalid_argument);
    CHECK_THROWS_AS(paired_ratio(std::vector<double>{}, std::vector<double>{}), std::invalid_argument);
}

TEST_CASE("the runner judges a case by its paired ratio", "[bench][registry]") {
    // every call lasts ~100 ms and one call makes a round (min_seconds 0), so each rate is
    // the call's units / ~0.1 s; the units of the warm-up and the three rounds are set so
    // that the rounds' ratios are ~4, ~1, ~1 (median ~1) while the ratio of the medians is ~2
    const std::vector<std::uint64_t> baseline_units{1, 1, 2, 4};
    const std::vector<std::uint64_t> candidate_units{1, 4, 2, 4};
    auto calls = std::make_shared<std::pair<std::size_t, std::size_t>>(0, 0);
    Case c;
    c.name = "paced";
    c.make = [=](Size) {
        const auto paced = [](std::uint64_t units) {
            std::this_thread::sleep_for(std::chrono::milliseconds(100));
            return units;
        };
        return Workload{[=] { return paced(baseline_units.at(calls->first++)); },
                        [=] { return paced(candidate_units.at(calls->second++)); }};
    };
    RunOptions options;
    options.repetitions = 3;
    options.min_seconds = 0;
    const auto result = run_case(c, options);
    CHECK(calls->first == 4);
    CHECK(calls->second == 4);
    // the sleeps overrun by a few ms at most: each rate within ~25 %
    CHECK_THAT(result.ratio, Catch::Matchers::WithinRel(1.0, 0.25));
    CHECK_THAT(result.ratio_max, Catch::Matchers::WithinRel(4.0, 0.25));
    CHECK_THAT(result.candidate_per_s / result.baseline_per_s, Catch::Matchers::WithinRel(2.0, 0.25));
}

TEST_CASE("a case with a parameter is selected whole by its name or by one row", "[bench][registry]") {
    int a = 0;
    Registry registry = registry_of({"serve/1", "sim", "serve/8"}, &a);
    const auto whole = registry.select("serve");
    REQUIRE(whole.size() == 2);
    CHECK(whole[0]->name == "serve/1");
    CHECK(whole[1]->name == "serve/8");
    REQUIRE(registry.select("serve/8").size() == 1);
    CHECK(registry.select("serve/8")[0]->name == "serve/8");
    CHECK(registry.select("sim").size() == 1);
    CHECK(registry.select("serve/2").empty());
    CHECK(registry.select("serve/").empty());
    CHECK(registry.select("sim/1").empty());
    CHECK(registry.select("ser").empty());
    // a name that would make another ambiguous is refused
    CHECK_THROWS_AS(registry.add(counting_case("serve", &a, &a)), std::invalid_argument);
    CHECK_THROWS_AS(registry.add(counting_case("sim/2", &a, &a)), std::invalid_argument);
}

TEST_CASE("a side that does no work is reported, not divided by", "[bench][registry]") {
    Case c;
    c.name = "idle";
    c.make = [](Size) { return Workload{[] { return std::uint64_t{0}; }, [] { return std::uint64_t{1}; }}; };
    CHECK_THROWS_AS(run_case(c, quick_options()), std::logic_error);
}
