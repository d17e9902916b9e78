#pragma once

#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "runs/evolve_config.hpp"
#include "runs/run_status.hpp"
#include "runs/treatment.hpp"

namespace stepstone::runs {

// A campaign is the paper's protocol as one resumable job: optional source
// runs, the knowledge base made from them (export of the best run, or merge
// of all), its randomized twin, then target runs = treatments x seeds. Each
// run is a `stepstone evolve` child process writing its own run file under
// the campaign directory; campaign.db indexes them. Every run is
// deterministic from its seed, so the campaign's results do not depend on
// --jobs, on threads, or on how often it was interrupted.

/// One step of runs: an evolve config, its seeds and generation budget.
struct RunStep {
    EvolveConfig config;               ///< the step's evolve config (its seed is replaced per run)
    std::vector<std::uint64_t> seeds;  ///< one run per seed
    int generations = 0;               ///< epochs after generation 0
};

/// Where the campaign's knowledge base comes from.
enum class KbFrom {
    best,   ///< export of the source run with the best reward (lowest seed on ties)
    merge,  ///< merge of every source run's KB, in seed order
    file,   ///< a KB file given in the config (no source step)
};

/// Where the seeded treatments' seeds come from (the campaign's `seed` block).
struct CampaignSeed {
    bool from_file = false;      ///< false: the best source run (highest best reward, lowest seed on ties)
    std::filesystem::path file;  ///< from_file: the source run file (absolute)
    std::string file_given;      ///< file as the config gives it (relative to the config's folder)
    SeedWith with = SeedWith::population;
    std::optional<int> count;  ///< absent: each target run's population size
};

/// A campaign config (stepstone campaign CONFIG.json).
struct CampaignConfig {
    std::optional<RunStep> source;
    KbFrom kb_from = KbFrom::best;
    std::filesystem::path kb_file;     ///< KbFrom::file: the KB to copy into the campaign (absolute)
    std::string kb_file_given;         ///< kb_file as the config gives it (relative to the config's folder)
    std::optional<double> kb_delta;    ///< set: the KB is coarsened to this delta (kb export --delta)
    std::uint64_t randomize_seed = 1;  ///< seed of the randomized KB (sum-rand, mo-rand)
    RunStep target;
    std::vector<Treatment> treatments;  ///< in the order given; each at most once
    /// Set when the config has a seed block or a seeded treatment (seed, seed-sum, ...).
    std::optional<CampaignSeed> seed;

    /// Strict parse. Keys: source {config, seeds | runs [+ first_seed],
    /// generations}, kb {from: best | merge} or {file}, with an optional
    /// delta (coarsen the KB to it), randomize_seed, seed {from: best} or
    /// {file}, with with and count (the seeded treatments' seeds),
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
    /// True when a treatment is seeded.
    bool seeded() const;
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

/// Writes `step`'s evolve config, with its generation budget, to `path` (the
/// file every run of the step is started with).
void write_step_config(const std::filesystem::path& path, const RunStep& step);

}  // namespace stepstone::runs
