#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

#include "core/progress.hpp"
#include "exp/campaign/campaign_cost.hpp"
#include "exp/campaign/campaign_kb.hpp"
#include "exp/evolution.hpp"
#include "runs/campaign_config.hpp"
#include "runs/campaign_store.hpp"

namespace stepstone::exp {

class MpiLeader;  // exp/mpi_evolve.hpp

/// The command line (program first) of a child process that carries out the
/// run of `options` and exits 0 when it finished, 130 when a signal stopped it.
using RunCommand = std::function<std::vector<std::string>(const EvolveOptions& options)>;

/// Options of `stepstone campaign`.
struct CampaignOptions {
    std::filesystem::path config_path;
    std::filesystem::path dir;
    /// How a child process carries out one run: its program and arguments for
    /// the run's options (the CLI gives `stepstone evolve` with the matching
    /// flags). Needed unless the runs go to MPI ranks.
    RunCommand run_command;
    unsigned jobs = 0;  ///< runs at a time; 0 = every core
    /// Evaluation threads per run; 0 = the cores shared out among the runs
    /// of a step that run at once (a lone source run gets every core).
    unsigned threads = 0;
    bool resume = false;
    /// Set on rank 0 of `campaign --mpi`: the runs go to the job's other
    /// ranks, one at a time each (exp/campaign_mpi.hpp), instead of child processes.
    MpiLeader* mpi = nullptr;
    ProgressMode progress = ProgressMode::automatic;
};

/// What a campaign did.
struct CampaignSummary {
    std::size_t runs = 0;
    std::size_t finished = 0;           ///< finished now or before
    std::size_t skipped = 0;            ///< already finished when resumed
    std::vector<std::string> failures;  ///< "file: error", one per failed run
    double wall_time = 0;
};

/// Runs (or resumes) a campaign into `dir`. A new campaign refuses a
/// directory that already holds campaign.db; --resume refuses a config that
/// differs from the stored one. Runs that fail are reported in the summary
/// (the others go on); a failed source step stops before the KB step.
/// Throws ConfigError for bad options or config, DatabaseError for an
/// unusable campaign.db.
CampaignSummary run_campaign(const CampaignOptions& options);

/// Returns if no run failed; otherwise writes one "campaign: failed: FILE:
/// ERROR" line per failed run to `err` and throws Error with their count and
/// the folder of their logs under `dir`.
void throw_on_failures(const CampaignSummary& summary, const std::filesystem::path& dir, std::ostream& err);

}  // namespace stepstone::exp
