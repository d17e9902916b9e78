#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "db/connection.hpp"
#include "kb/knowledge_base.hpp"
#include "runs/run_status.hpp"
#include "sim/episode.hpp"

namespace stepstone::runs {

/// The name evolve gives the knowledge base it stores in a run file.
inline constexpr const char* kRunKbName = "run";

/// The `run` row of a run file.
struct RunRecord {
    std::int64_t id = 0;
    std::string task;
    std::string treatment = "none";
    std::int64_t seed = 0;
    nlohmann::json config;                  ///< effective config, seed included
    RunStatus status = RunStatus::running;  ///< running | finished
    int generations = 0;                    ///< generations asked for
    int generations_done = -1;              ///< last committed generation (-1: none yet)
    std::int64_t evaluations = 0;
    std::int64_t nan_outputs = 0;
};

/// One evaluated individual as stored in the `individual` table.
struct IndividualRow {
    std::int64_t id = 0;
    int generation = 0;
    std::optional<std::int64_t> parent_id;
    double reward = 0;
    double fitness = 0;
    double diversity = 0;
    std::optional<double> r_max;  ///< the policy's KB score, absent without a KB
    int balls = 0;
    long steps = 0;
    sim::Milestones milestones;  ///< presses, pickups, carry_steps, basket_releases (schema 0005)
};

/// The statistics of one generation (`generation` table).
struct GenerationRow {
    int generation = 0;
    double best_reward = 0;
    double mean_reward = 0;
    double median_reward = 0;
    std::vector<std::size_t> front_sizes;
    double diversity_min = 0;
    double diversity_max = 0;
    std::int64_t evaluations = 0;
    double wall_time = 0;        ///< seconds, the whole generation
    double time_simulation = 0;  ///< seconds evaluating
    double time_kb = 0;          ///< seconds observing into the knowledge base
    double time_diversity = 0;   ///< seconds computing diversity
    double time_selection = 0;   ///< seconds sorting, crowding, selecting
    double time_database = 0;    ///< seconds writing the generation (set by write_generation)
};

/// A genome kept for replay.
struct GenomeRow {
    std::int64_t individual_id = 0;
    std::string genome_json;
};

/// Everything one generation writes, committed in one transaction.
struct GenerationWrite {
    GenerationRow stats;
    std::vector<IndividualRow> individuals;
    std::vector<GenomeRow> genomes;
    nlohmann::json checkpoint;     ///< the state to resume from
    std::int64_t nan_outputs = 0;  ///< NaN network outputs in this generation's evaluations
    /// The run's knowledge base when this generation observed into it (else null):
    /// its segments from kb_previous_size on and those credited now are written.
    const kb::KnowledgeBase* kb = nullptr;
    std::int64_t kb_id = 0;
    std::size_t kb_previous_size = 0;
};

/// Inserts a new run row and returns its id.
std::int64_t insert_run(db::Connection& connection, const RunRecord& run, const std::string& program_version);

/// The run of a run file; throws DatabaseError if the file has none or more than one.
RunRecord load_run(db::Connection& connection);

/// Whether the file holds a run (a KB file holds none).
bool holds_run(db::Connection& connection);

/// The best task reward of any generation of the file's run; nullopt before its first generation.
std::optional<double> best_reward(db::Connection& connection);

/// What a run's file says of its cost (campaign --dry-run's probe): the mean seconds of a
/// generation after generation 0 beside simulation and KB lookups, the evaluations, and
/// the file's bytes by part (the pages of each table and its indexes).
struct RunFileCost {
    double other_s = 0;
    double evaluations = 0;
    double individual_bytes = 0;  ///< the rows of every evaluation
    double generation_bytes = 0;  ///< genomes and generation rows
    double kb_bytes = 0;          ///< the KB's segments and provenance
    double total_bytes = 0;       ///< the whole file
};
RunFileCost run_file_cost(db::Connection& connection);

/// Writes a generation and updates the run's counters, in one transaction:
/// a crash loses at most the generation in progress.
void write_generation(db::Connection& connection, RunRecord& run, const GenerationWrite& write);

/// Marks the run finished (after its last generation).
void update_run(db::Connection& connection, const RunRecord& run);

/// The checkpoint of a run; nullopt before its first generation committed.
std::optional<nlohmann::json> load_checkpoint(db::Connection& connection, std::int64_t run_id);

/// A stored genome and the reward recorded for it.
struct StoredGenome {
    std::int64_t individual_id = 0;
    nlohmann::json genome;
    double reward = 0;
    int balls = 0;
    int generation = 0;
};

/// The genome of `individual_id`; throws DataError if it was not stored.
StoredGenome load_genome(db::Connection& connection, std::int64_t run_id, std::int64_t individual_id);
/// The ids of the run's stored genomes, in increasing order.
std::vector<std::int64_t> stored_individuals(db::Connection& connection, std::int64_t run_id);
/// The stored genome with the highest task reward (lowest id on ties).
StoredGenome load_best_genome(db::Connection& connection, std::int64_t run_id);
/// The `count` stored genomes with the highest task reward, highest first
/// (lowest id on ties); fewer when fewer are stored.
std::vector<StoredGenome> load_best_genomes(db::Connection& connection, std::int64_t run_id,
                                            std::int64_t count);

}  // namespace stepstone::runs
