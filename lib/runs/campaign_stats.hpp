#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <ostream>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "runs/campaign_events.hpp"
#include "runs/treatment.hpp"
#include "stats/mann_whitney.hpp"
#include "stats/summary.hpp"

namespace stepstone::runs {

/// One target run of a campaign as the statistics see it.
struct RunCurve {
    Treatment treatment = Treatment::none;
    std::uint64_t seed = 0;
    std::string file;  ///< relative to the campaign directory
    /// Best-of-run task reward up to each generation (index = generation):
    /// the running maximum of the generation table's best_reward.
    std::vector<double> best;
    std::int64_t policies = 0;       ///< policies evaluated up to the chosen generation
    std::int64_t ball_policies = 0;  ///< of those, the ones that collected at least one ball
    /// Mean r_max of the policies evaluated in the signal window (generations
    /// CampaignStats::signal_from to the chosen one); absent without a KB.
    std::optional<double> mean_r_max;
    /// First generation (up to the chosen one) each milestone was reached;
    /// absent when the file does not record milestones (older than schema 0005).
    std::optional<FirstEvents> first_events;
};

/// One treatment at the chosen generation.
struct TreatmentResult {
    Treatment treatment = Treatment::none;
    std::vector<double> best;        ///< best-of-run reward of each run, in seed order
    stats::Summary summary;          ///< of `best`
    std::size_t successes = 0;       ///< runs with best >= threshold
    std::int64_t policies = 0;       ///< summed over the runs
    std::int64_t ball_policies = 0;  ///< summed over the runs
    /// Mean over the runs of their mean_r_max; absent without a KB.
    std::optional<double> mean_r_max;
};

/// Below this many runs in either arm, or from this share of tied values in
/// the pooled sample, a Mann-Whitney p is the permutation p (docs/statistics.md).
inline constexpr std::size_t kPermutationBelowRuns = 20;
inline constexpr double kPermutationTiedShare = 0.25;

/// How the p of a PairTest was obtained.
enum class PairMethod {
    exact,        ///< SciPy's exact distribution (no ties, a sample of at most 8)
    normal,       ///< the normal approximation (large samples, few ties)
    permutation,  ///< every relabelling counted, ties kept
    monte_carlo,  ///< seeded random relabellings, with a standard error
};
/// "exact", "normal", "permutation", "monte-carlo".
std::string_view to_string(PairMethod method);

/// Mann-Whitney U between two treatments at the chosen generation.
struct PairTest {
    Treatment a = Treatment::none, b = Treatment::none;
    std::size_t n_a = 0, n_b = 0;
    stats::MannWhitney test;  ///< u is treatment a's U statistic; p with SciPy's method="auto"
    double tied_share = 0;    ///< share of the pooled values in groups of equal values
    /// The p reported (and Holm-adjusted): the permutation p for small or tied
    /// samples, else test.p.
    double p = 1;
    PairMethod method = PairMethod::normal;
    double p_standard_error = 0;  ///< of a Monte Carlo p (0 otherwise)
    double p_holm = 1;            ///< Holm-adjusted over every pair of the campaign
    double a12 = 0.5;             ///< Vargha-Delaney A12 of a over b
};

/// Mann-Whitney U of every pair of treatments on their best-of-run rewards (a
/// before b in the given order), Holm-adjusted over the pairs; the permutation
/// p below kPermutationBelowRuns runs an arm or with many ties.
std::vector<PairTest> pair_tests(std::span<const TreatmentResult> treatments);

/// One row of a runs CSV (write_runs_csv, read back by pool_stats).
struct RunRow {
    Treatment treatment = Treatment::none;
    std::uint64_t seed = 0;
    int generation = 0;
    double best_reward = 0;
    bool success = false;
    std::int64_t policies = 0;
    std::int64_t ball_policies = 0;
    std::optional<double> mean_r_max;
};
/// The figures of treatment `t` from its rows of `runs` (other treatments'
/// skipped): best rewards in row order, their summary, the successes at
/// `threshold`, the policy counts summed, the mean of the runs' mean_r_max.
TreatmentResult treatment_result(Treatment t, std::span<const RunRow> runs, double threshold);
/// `treatment,seed,generation,best_reward,success,policies,ball_policies,mean_r_max`
/// with a header line; mean_r_max empty when absent, numbers to 17 digits.
void write_run_rows(std::ostream& out, std::span<const RunRow> rows);
/// The tests CSV of `tests` (write_tests_csv's format).
void write_pair_tests_csv(std::ostream& out, std::span<const PairTest> tests);
/// The per-treatment table (runs, successes, quartiles, max of the best
/// rewards) and the shaping-signal table, r_max described by `signal`.
void write_treatment_tables(std::ostream& out, std::span<const TreatmentResult> treatments,
                            std::string_view signal, int generation);
/// The Mann-Whitney table of `tests` at `generation` (nothing without tests).
void write_pair_tests(std::ostream& out, std::span<const PairTest> tests, int generation);

/// The statistics of a campaign's target runs (the paper's Fig. 6 and 7 and
/// its appendix table).
struct CampaignStats {
    std::string dir;
    int generation = 0;
    double threshold = 0.5;
    int signal_from = 0;         ///< first generation of the signal window (the last of it: `generation`)
    std::vector<RunCurve> runs;  ///< target runs, in campaign order
    std::vector<TreatmentResult> treatments;  ///< in campaign order
    /// successes[g][t]: runs of treatment t that succeeded by generation g (0..generation).
    std::vector<std::vector<std::size_t>> successes;
    std::vector<PairTest> tests;  ///< every pair (a before b in campaign order)
    /// Target runs left out because they are missing or have not reached
    /// `generation` (only with `available_only`), relative to the campaign directory.
    std::vector<std::string> skipped;
    /// Kaplan-Meier and log-rank statistics of the milestones; absent when a
    /// run does not record them (listed in `unrecorded`).
    std::optional<CampaignEvents> events;
    std::vector<std::string> unrecorded;  ///< run files without milestones, relative to the directory
};

/// Reads every target run of the campaign in `dir` (read-only) and computes
/// the statistics at `generation` (default: the campaign's target budget).
/// A run succeeds when its best-of-run reward reaches `threshold`. Throws
/// ConfigError for a threshold outside [0, 1] or a negative generation;
/// DataError naming the file when a run file is missing, is not a run of this
/// campaign (seed or treatment differ), or has not reached `generation`;
/// DatabaseError for an unreadable file. With `available_only` (a campaign
/// still running), runs that are missing or short of `generation` are left
/// out and listed in `skipped` instead; DataError if no run is left. The
/// shaping signal is the mean r_max of the last `signal_window` generations
/// up to `generation` (ConfigError below 1).
CampaignStats campaign_stats(const std::filesystem::path& dir, std::optional<int> generation,
                             double threshold, bool available_only = false, int signal_window = 10);

/// The text report: per-treatment summary, the shaping signal and the
/// policies that collected a ball, success counts along generations, the
/// pairwise tests, and the time to `event` with its log-rank tests.
void write_text(std::ostream& out, const CampaignStats& stats, Milestone event = Milestone::pickup);
/// Success counts per generation: `generation,<treatment>...`.
void write_success_csv(std::ostream& out, const CampaignStats& stats);
/// Throws DataError naming the runs that do not record milestones, if any.
void require_events(const CampaignStats& stats);
/// The runs' first events (`treatment,seed,event,generation,observed`);
/// DataError naming the runs when they do not record milestones.
void write_events_csv(std::ostream& out, const CampaignStats& stats);
/// The log-rank tests of every milestone; DataError as write_events_csv.
void write_logrank_csv(std::ostream& out, const CampaignStats& stats);
/// The hazard ratios and RMSTs of every milestone (write_hazard_csv of the
/// events); DataError as write_events_csv.
void write_hazard_csv(std::ostream& out, const CampaignStats& stats);
/// One row per run: `treatment,seed,generation,best_reward,success,policies,
/// ball_policies,mean_r_max` (mean_r_max empty without a KB).
void write_runs_csv(std::ostream& out, const CampaignStats& stats);
/// One row per pair: `treatment_a,treatment_b,n_a,n_b,u,p,p_holm,a12,method,p_auto,p_se`
/// (p_auto: SciPy's method="auto" p; p_se: a Monte Carlo p's standard error, else empty).
void write_tests_csv(std::ostream& out, const CampaignStats& stats);

}  // namespace stepstone::runs
