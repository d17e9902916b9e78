#pragma once

// How a campaign carries out its runs: the Runner keeps campaign.db's rows
// and the progress line, and hands each run, as the arguments of its
// `stepstone evolve`, to an executor that runs it somewhere (a child process
// here; an MPI rank in campaign_mpi.cpp). Internal to lib/exp.

#include <cstddef>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/progress.hpp"
#include "db/connection.hpp"
#include "exp/campaign/campaign.hpp"

namespace stepstone::exp {

/// One run to carry out: the `stepstone evolve` of one run file, its
/// output appended to `log`.
struct RunLaunch {
    std::size_t index = 0;         ///< in the campaign's runs
    std::filesystem::path config;  ///< the step's evolve config
    std::filesystem::path db;      ///< the run file (resumed when it exists)
    std::uint64_t seed = 0;
    int generations = 0;
    unsigned threads = 1;
    bool resume = false;
    std::optional<std::filesystem::path> kb;   ///< the shaping KB of a target run that uses one
    std::optional<runs::Treatment> treatment;  ///< set with kb: its shaping treatment
    std::optional<std::filesystem::path> seed_from;  ///< the seed source of a seeded target run
    std::optional<runs::SeedWith> seed_with;         ///< set with seed_from
    std::optional<int> seed_count;                   ///< set with seed_from when the campaign gives one
    std::filesystem::path log;

    /// The engine's options for this run, whether a child process or an MPI
    /// rank carries it out: quiet, stopped by SIGINT and SIGTERM.
    EvolveOptions evolve_options() const;
};

/// How a launched run ended.
struct RunEnd {
    std::size_t index = 0;
    bool ok = false;       ///< the evolve ended with success (the run file is then checked)
    std::string error;     ///< otherwise: why, in one line
    bool stopped = false;  ///< it stopped on a signal after committing its generation (exit 130)
};

/// Carries out runs, several at a time.
class RunExecutor {
public:
    virtual ~RunExecutor() = default;
    /// Runs that can go at once.
    virtual std::size_t slots() const = 0;
    /// Evaluation threads of each run when `at_once` runs of a step go together
    /// and the user gave none.
    virtual unsigned default_threads(std::size_t at_once) const = 0;
    /// Starts a run; at most slots() are started and not yet returned by wait().
    virtual void start(const RunLaunch& launch) = 0;
    /// Waits a moment (about 0.1 s) and returns the runs that ended meanwhile.
    virtual std::vector<RunEnd> wait() = 0;
    /// True when the runs write on this host, so that a running run's file
    /// may be read for progress. SQLite's WAL index is shared memory: a file
    /// being written on another host (an MPI rank's) is not read until its
    /// run ended.
    virtual bool runs_here() const { return true; }
    /// Asks every started run to stop after its current generation (SIGTERM
    /// to a child process). The MPI executor notices a stop by itself.
    virtual void interrupt() {}
};

/// Runs each run as a `stepstone evolve` child process of `program`, `jobs`
/// at a time (0: every core), the cores shared out among them.
std::unique_ptr<RunExecutor> make_process_executor(RunCommand command, unsigned jobs);

/// Carries out a campaign's runs through an executor, keeping their rows of
/// campaign.db (the only writer there) and the progress line up to date.
class Runner {
public:
    Runner(const CampaignOptions& options, db::Connection& connection, std::vector<runs::CampaignRun>& runs,
           Progress& progress, RunExecutor& executor);

    /// The seed source of the seeded target runs, and the campaign's seed
    /// settings (its with and count); set before they are executed.
    void set_seeding(std::filesystem::path source, const runs::CampaignSeed& seed);

    /// Runs the runs `indices` to the end (finished ones on disk are only
    /// recorded, in `summary.skipped`); returns the failures, "file: error".
    /// Once SIGINT or SIGTERM arrived (under an InterruptGuard) no run is
    /// started, the running ones are asked to stop after their generation and
    /// waited for, and the stopped ones are recorded pending; the caller then
    /// sees InterruptGuard::received().
    std::vector<std::string> execute(const std::vector<std::size_t>& indices, CampaignSummary& summary);

private:
    struct Active {
        std::size_t index = 0;
        double started = 0;
    };

    std::optional<runs::RunFileState> existing_state(std::size_t k);
    void mark_finished(std::size_t k, const runs::RunFileState& on_disk, double wall_time);
    RunLaunch launch_of(std::size_t k, unsigned threads) const;
    std::optional<std::string> finish(const Active& done, const RunEnd& end);
    void report(const std::vector<Active>& active);

    /// Seconds between two readings of the running runs' files for the progress line: the
    /// executor wakes every 100 ms, and opening each running file as often was a visible share of
    /// a core for the campaign process (docs/transfer.md has the measurement).
    static constexpr double kReadingPeriod = 1.0;

    const CampaignOptions& options_;
    db::Connection& connection_;
    std::vector<runs::CampaignRun>& runs_;
    Progress& progress_;
    RunExecutor& executor_;
    double last_reading_ = -kReadingPeriod;  ///< now_seconds() of the last reading of the run files
    std::optional<std::filesystem::path> seed_source_;
    runs::CampaignSeed seed_;
};

/// The log file of `run` under `dir`: logs/<file with / as ->.log.
std::filesystem::path run_log_path(const std::filesystem::path& dir, const runs::PlannedRun& run);

}  // namespace stepstone::exp
