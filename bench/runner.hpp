#pragma once

#include <functional>
#include <span>
#include <string>
#include <vector>

#include "bench/registry.hpp"

namespace stepstone::bench {

/// How a case is timed.
struct RunOptions {
    Size size = Size::full;    ///< workload size passed to Case::make
    int repetitions = 5;       ///< alternating baseline/candidate rounds (>= 1)
    double min_seconds = 0.3;  ///< each side runs at least this long per round
};

/// Options for a normal run: paper-size workloads, 5 rounds of >= 0.3 s.
RunOptions full_options();
/// Options for `--quick`: reduced workloads, 3 rounds of >= 0.03 s, so the
/// whole run stays within a few seconds.
RunOptions quick_options();

/// The ratios candidate / baseline of the rounds of one case, each round's
/// candidate rate over the same round's baseline rate, summarised.
struct PairedRatio {
    double median = 0;  ///< type-7 median of the rounds' ratios (even count: mean of the middle two)
    double min = 0;     ///< the lowest round's ratio
    double max = 0;     ///< the highest round's ratio
};

/// Pairs the rates round by round: ratio i = candidate_rates[i] / baseline_rates[i].
/// Throws std::invalid_argument if the lists are empty or differ in length.
PairedRatio paired_ratio(std::span<const double> baseline_rates, std::span<const double> candidate_rates);

/// Throughput of both sides of one case.
struct CaseResult {
    std::string name;            ///< the case's name
    std::string unit;            ///< the case's unit of work
    double baseline_per_s = 0;   ///< median over rounds of baseline units per second
    double candidate_per_s = 0;  ///< median over rounds of candidate units per second
    double ratio = 0;         ///< the paired ratio: median over rounds of each round's candidate / baseline
    double ratio_min = 0;     ///< the lowest round's ratio
    double ratio_max = 0;     ///< the highest round's ratio
    double target_ratio = 0;  ///< the case's target
    std::vector<double> baseline_rates;   ///< each round's baseline units per second
    std::vector<double> candidate_rates;  ///< each round's candidate units per second
    /// Why the case could not run (no mpirun, a failed child, ...); empty when it ran.
    std::string skipped;
};

/// Called after each round with (rounds done, rounds in total).
using RoundCallback = std::function<void(int, int)>;

/// Builds the case's workload, runs one untimed call of each side (warm-up),
/// then `repetitions` rounds that time the baseline and the candidate one
/// after the other, alternating which goes first. Each side's rate in a round
/// is units / seconds over as many calls as fit in `min_seconds` (at least
/// one); the reported rates are the medians over rounds and the ratio is
/// paired_ratio's, so that a round whose machine ran slow for both sides
/// counts as one round. Throws std::logic_error if a side reports zero units.
CaseResult run_case(const Case& c, const RunOptions& options, const RoundCallback& on_round = {});

}  // namespace stepstone::bench
