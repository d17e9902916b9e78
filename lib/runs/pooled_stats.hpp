#pragma once

// The statistics of runs pooled from the CSVs of several campaigns: the same
// design finished on two machines, or a campaign whose run files are gone but
// whose `stats --runs-csv/--events-csv` exports were kept.

#include <filesystem>
#include <ostream>
#include <span>
#include <string>
#include <vector>

#include "runs/campaign_events.hpp"
#include "runs/campaign_stats.hpp"

namespace stepstone::runs {

/// A run found in more than one input: the inputs agree on every field.
struct RepeatedRun {
    Treatment treatment = Treatment::none;
    std::uint64_t seed = 0;
    std::vector<std::string> files;  ///< the runs CSVs that hold it, in input order
};

/// The pooled runs and their statistics at the one generation they share.
struct PooledStats {
    std::vector<std::string> runs_files, events_files;
    int generation = 0;
    double threshold = 0.5;
    std::vector<RunRow> runs;                 ///< seed order, then treatment order (a campaign's)
    std::vector<RunEvents> run_events;        ///< the same order
    std::vector<TreatmentResult> treatments;  ///< in the order of first appearance
    std::vector<PairTest> tests;              ///< Mann-Whitney on the best rewards, Holm over the pairs
    CampaignEvents events;                    ///< Kaplan-Meier and log-rank of every milestone
    std::vector<RepeatedRun> repeated;        ///< runs in more than one input
};

/// Reads runs CSVs (`stats --runs-csv`) and events CSVs (`stats --events-csv`)
/// and computes the statistics of their union. A run (treatment and seed) may
/// appear in several inputs only with identical rows (listed in `repeated`).
/// Throws ConfigError for no input or a threshold outside [0, 1]; DataError
/// naming the file and line for a malformed CSV, naming the run when two
/// inputs disagree on it, when a run lacks its events (or events lack their
/// run), or when the runs were compared at different generations; IoError
/// for an unreadable file.
PooledStats pool_stats(std::span<const std::filesystem::path> runs_files,
                       std::span<const std::filesystem::path> events_files, double threshold);

/// The text report: the inputs, the per-treatment tables, the Mann-Whitney
/// tests and the time to `event` with its log-rank tests.
void write_pooled_text(std::ostream& out, const PooledStats& stats, Milestone event);

}  // namespace stepstone::runs
