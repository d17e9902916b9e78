#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "runs/campaign_config.hpp"

namespace stepstone::exp {

/// The cost of one kind of run of a campaign, from a timing probe of this
/// machine (one core).
struct RunKindCost {
    std::string kind;  ///< "source", "target none", "target sum", ...
    std::int64_t runs = 0;
    int generations = 0;           ///< per run, after generation 0
    std::int64_t evaluations = 0;  ///< per run
    double simulation_s = 0;       ///< per evaluation, every start run to its last step
    double lookup_s = 0;           ///< per evaluation: r_max at full length (shaped kinds)
    bool lookups_unknown = false;  ///< shaped, but the KB does not exist yet
    double other_s = 0;            ///< per generation: diversity, selection, the KB's observations, the file
    // the run file, from where the probe run's file keeps its bytes
    double bytes_fixed = 0;               ///< schema, run row, the latest checkpoint
    double bytes_per_evaluation = 0;      ///< the `individual` rows
    double bytes_per_generation = 0;      ///< the kept genomes and the `generation` row
    double kb_bytes_per_observation = 0;  ///< the KB's segments of the first observation (source runs)
    int observations = 0;                 ///< generations that observe into the KB, per run
    double cpu_seconds() const;           ///< one run
    /// One run's file: fixed + evaluations x per evaluation + generations x per generation +
    /// observations x the first observation's KB bytes. Every observation after the first adds
    /// fewer new segments than it (the KB keeps each distinct one once), so that term bounds the KB.
    double bytes() const;
};

/// The campaign's cost, as printed by --dry-run: counts, and an estimate
/// from a probe of a few generations of each kind of run.
struct CampaignCost {
    std::int64_t runs = 0;
    std::int64_t evaluations = 0;  ///< policy evaluations over every run
    double robot_steps = 0;        ///< were every evaluation to run its full episode
    double steps_per_second = 0;   ///< one core, measured now on full-length random policies
    std::vector<RunKindCost> kinds;
    double probe_seconds = 0;  ///< how long the probe took
    double cpu_seconds = 0;    ///< the estimate: sum over kinds of runs x cpu_seconds()
    double bytes = 0;          ///< run files, KBs aside
};

/// Counts evaluations and robot steps, then times this machine on each kind
/// of run of `config`: real generations (a run file in a temporary folder,
/// population and task of the step, one thread) for what a generation costs
/// beside simulation, full-length episodes for simulation, and r_max lookups
/// of full-length behaviours in the campaign's KB for shaped runs. The KB is
/// `config`'s kb.file, or kb/kb.db of `dir` when an earlier run of the
/// campaign made it; otherwise shaped runs count no lookups, and say so.
/// `probe_seconds` bounds the simulation and lookup timings of each kind.
CampaignCost estimate_cost(const runs::CampaignConfig& config, const std::filesystem::path& dir = {},
                           double probe_seconds = 0.5);

/// The plan of `config` and its estimated cost, as text.
void write_plan(std::ostream& out, const runs::CampaignConfig& config, const CampaignCost& cost,
                unsigned jobs);

}  // namespace stepstone::exp
