#include "bench/runner.hpp"

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "stats/summary.hpp"

namespace stepstone::bench {

namespace {

using Clock = std::chrono::steady_clock;

// units per second of repeated calls lasting at least min_seconds
double measure(const Work& work, double min_seconds, const std::string& what) {
    std::uint64_t units = 0;
    const auto start = Clock::now();
    double elapsed = 0;
    do {
        const std::uint64_t done = work();
        if (done == 0) throw std::logic_error("bench case " + what + " did no work");
        units += done;
        elapsed = std::chrono::duration<double>(Clock::now() - start).count();
    } while (elapsed < min_seconds);
    return static_cast<double>(units) / elapsed;
}

}  // namespace

PairedRatio paired_ratio(std::span<const double> baseline_rates, std::span<const double> candidate_rates) {
    if (baseline_rates.empty() || baseline_rates.size() != candidate_rates.size())
        throw std::invalid_argument("paired_ratio: " + std::to_string(baseline_rates.size()) +
                                    " baseline and " + std::to_string(candidate_rates.size()) +
                                    " candidate rates");
    std::vector<double> ratios;
    for (std::size_t i = 0; i < baseline_rates.size(); ++i)
        ratios.push_back(candidate_rates[i] / baseline_rates[i]);
    const auto [low, high] = std::minmax_element(ratios.begin(), ratios.end());
    return PairedRatio{stats::median(ratios), *low, *high};
}

RunOptions full_options() { return RunOptions{}; }

RunOptions quick_options() {
    RunOptions options;
    options.size = Size::quick;
    options.repetitions = 3;
    options.min_seconds = 0.03;
    return options;
}

CaseResult run_case(const Case& c, const RunOptions& options, const RoundCallback& on_round) {
    const int rounds = std::max(1, options.repetitions);
    const Workload workload = c.make(options.size);

    // warm-up: caches, page faults and lazy allocations stay out of the rates
    workload.baseline();
    workload.candidate();

    // alternate the order so neither side always runs on a cooler or hotter core
    std::vector<double> baseline_rates;
    std::vector<double> candidate_rates;
    for (int round = 0; round < rounds; ++round) {
        if (round % 2 == 0) {
            baseline_rates.push_back(measure(workload.baseline, options.min_seconds, c.name + " (baseline)"));
            candidate_rates.push_back(
                measure(workload.candidate, options.min_seconds, c.name + " (candidate)"));
        } else {
            candidate_rates.push_back(
                measure(workload.candidate, options.min_seconds, c.name + " (candidate)"));
            baseline_rates.push_back(measure(workload.baseline, options.min_seconds, c.name + " (baseline)"));
        }
        if (on_round) on_round(round + 1, rounds);
    }

    CaseResult result;
    result.name = c.name;
    result.unit = c.unit;
    result.baseline_per_s = stats::median(baseline_rates);
    result.candidate_per_s = stats::median(candidate_rates);
    const PairedRatio paired = paired_ratio(baseline_rates, candidate_rates);
    result.ratio = paired.median;
    result.ratio_min = paired.min;
    result.ratio_max = paired.max;
    result.target_ratio = c.target_ratio;
    result.baseline_rates = std::move(baseline_rates);
    result.candidate_rates = std::move(candidate_rates);
    return result;
}

}  // namespace stepstone::bench
