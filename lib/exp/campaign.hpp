#pragma once

#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "core/progress.hpp"
#include "exp/evolve_config.hpp"
#include "exp/run_status.hpp"
#include "exp/treatment.hpp"

namespace stepstone::exp {

// A campaign is the paper's protocol as one resumable job: optional source
// runs, the knowledge base made from them (export of the best run, or merge
// of all), its randomized twin, then target runs = treatments x seeds. Each
// run is a `stepstone evolve` child process writing its own run file under
// the campaign directory; campaign.db indexes them. Every run is
// deterministic from its seed, so the campaign's results do not depend on
// --jobs, on threads, or on how often it was interrupted.

/// One step of runs: an evolve config, its seeds and generation budget.
struct RunStep {
    EvolveConfig config;              ///< the step's evolve config (its seed is replaced per run)
    std::vector<std::uint64_t> seeds;  ///< one run per seed
    int generations = 0;              ///< epochs after generation 0
};

/// Where the campaign's knowledge base comes from.
enum class KbFrom {
    best,   ///< export of the source run with the best reward (lowest seed on ties)
    merge,  ///< merge of every source run's KB, in seed order
    file,   ///< a KB file given in the config (no source step)
};

/// A campaign config (stepstone campaign CONFIG.json).
struct CampaignConfig {
    std::optional<RunStep> source;
    KbFrom kb_from = KbFrom::best;
    std::filesystem::path kb_file;       ///< KbFrom::file: the KB to copy into the campaign
    std::optional<double> kb_delta;      ///< set: the KB is coarsened to this delta (kb export --delta)
    std::uint64_t randomize_seed = 1;    ///< seed of the randomized KB (sum-rand, mo-rand)
    RunStep target;
    std::vector<Treatment> treatments;   ///< in the order given; each at most once

    /// Strict parse. Keys: source {config, seeds | runs [+ first_seed],
    /// generations}, kb {from: best | merge} or {file}, with an optional
    /// delta (coarsen the KB to it), randomize_seed,
    /// target {config, seeds | runs [+ first_seed], generations, treatments}.
    /// A step's `config` is a file name (relative to `base`) or an inline
    /// evolve config. Throws ConfigError naming `source_name` and the key.
    static CampaignConfig from_json(const nlohmann::json& json, const std::string& source_name,
                                    const std::filesystem::path& base);
    /// Reads and parses a campaign config file.
    static CampaignConfig load(const std::filesystem::path& path);
    /// The effective config (step configs inline), as stored in campaign.db.
    nlohmann::json to_json() const;
    /// True when a treatment needs a KB (any but none).
    bool needs_kb() const;
    /// True when a treatment needs the randomized KB.
    bool needs_randomized_kb() const;
};

/// One planned run.
struct PlannedRun {
    CampaignStep step = CampaignStep::target;
    Treatment treatment = Treatment::none;
    std::uint64_t seed = 0;
    std::string file;  ///< relative to the campaign directory, e.g. "target/sum/seed-3.db"
    int generations = 0;
};

/// Every run of the campaign in order: source runs by seed, then target runs
/// by seed then treatment (config order), so that an interrupted campaign has
/// as many finished runs in every treatment (give or take one).
std::vector<PlannedRun> plan_runs(const CampaignConfig& config);

/// The campaign's cost, as printed by --dry-run.
struct CampaignCost {
    std::int64_t runs = 0;
    std::int64_t evaluations = 0;       ///< policy evaluations over every run
    double robot_steps = 0;             ///< upper bound: every evaluation runs its full episode
    double steps_per_second = 0;        ///< one core, measured now on full-length random policies
    double cpu_seconds = 0;             ///< robot_steps / steps_per_second
};

/// Counts evaluations and robot steps and times the simulator for a moment
/// (about `measure_seconds`) to turn them into a CPU-time upper bound.
CampaignCost estimate_cost(const CampaignConfig& config, double measure_seconds = 0.3);

/// Options of `stepstone campaign`.
struct CampaignOptions {
    std::filesystem::path config_path;
    std::filesystem::path dir;
    std::filesystem::path program;  ///< the stepstone binary that runs each `evolve` (empty: this process's own)
    unsigned jobs = 0;              ///< runs at a time; 0 = every core
    /// Evaluation threads per run; 0 = the cores shared out among the runs
    /// of a step that run at once (a lone source run gets every core).
    unsigned threads = 0;
    bool resume = false;
    ProgressMode progress = ProgressMode::automatic;
};

/// What a campaign did.
struct CampaignSummary {
    std::size_t runs = 0;
    std::size_t finished = 0;   ///< finished now or before
    std::size_t skipped = 0;    ///< already finished when resumed
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

/// Writes the gzip file `in` uncompressed to `out` (a shipped KB such as
/// examples/fixtures/demo_kb.db.gz). Throws DataError naming `in` when it is
/// not whole gzip data, Error when `out` cannot be written.
void gunzip_file(const std::filesystem::path& in, const std::filesystem::path& out);

/// A run as campaign.db lists it: its plan and where it stands.
struct IndexedRun {
    PlannedRun run;
    RunStatus status = RunStatus::pending;
};

/// Where a campaign's runs and KBs are, read from campaign.db.
struct CampaignIndex {
    nlohmann::json config;
    std::vector<IndexedRun> runs;  ///< in plan order
};
/// Reads campaign.db of `dir`; throws DatabaseError / DataError naming the file.
CampaignIndex load_campaign(const std::filesystem::path& dir);

/// The run files of a campaign directory and what they hold, as a text table.
void write_plan(std::ostream& out, const CampaignConfig& config, const CampaignCost& cost, unsigned jobs);

}  // namespace stepstone::exp
