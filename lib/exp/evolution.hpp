#pragma once

#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/progress.hpp"
#include "evo/diversity_matrix.hpp"
#include "exp/evaluation.hpp"
#include "kb/knowledge_base.hpp"
#include "nn/genome.hpp"
#include "runs/evolve_config.hpp"
#include "runs/run_store.hpp"

namespace stepstone::exp {

class MpiLeader;  // exp/mpi_evolve.hpp

/// One member of the population between generations.
struct Member {
    std::int64_t id = 0;
    std::optional<std::int64_t> parent_id;
    nn::Genome genome{1, 1};  // replaced before use
    double reward = 0;
    int balls = 0;
    long steps = 0;
    sim::Milestones milestones;  ///< written with its individual row only (not checkpointed)
    evo::Trajectory cells;
    std::optional<double> r_max;     ///< shaping from the run's shaping KB, absent without one
    std::vector<double> objectives;  ///< the objectives in the selection that kept it
    double crowding = 0;             ///< crowding distance in that selection
};

/// Evaluates a generation's genomes somewhere else than this process's
/// threads (exp/mpi_evolve.hpp: over the ranks of an MPI job), and the
/// distances of the diversity objective with them. Result k
/// belongs to genome k, with its r_max when the run has a shaping KB, and
/// equals what evaluate_genome and shaped_r_max give here.
class RemoteEvaluator {
public:
    virtual ~RemoteEvaluator() = default;
    /// `behaviours`, when not null, receives genomes.size() x behaviour_size()
    /// floats, genome by genome. Throws EvaluationInterrupted when the
    /// evaluations are abandoned (a signal, a rank lost).
    virtual std::vector<Evaluation> evaluate(const std::vector<nn::Genome>& genomes,
                                             std::vector<float>* behaviours) = 0;
    /// The diversity's new distances (evo::PairDistances), computed there
    /// too; equal to evo::pair_distances here. Throws EvaluationInterrupted
    /// as evaluate() does.
    virtual std::vector<float> distances(std::span<const evo::PositionPair> pairs,
                                         std::span<const evo::Trajectory> trajectories,
                                         std::size_t length) = 0;
};

/// A policy's r_max under the shaping KB `kb`, from its first start's
/// behaviour matrix.
double shaped_r_max(const kb::KnowledgeBase& kb, std::span<const float> behaviour);

/// The source-task evolution of the paper (NSGA-II on task reward and
/// behavioural diversity; docs/original.md), one generation at a time. Each
/// generation returns what it writes to the run file; the state between
/// generations is plain data (checkpoint()), and every random draw comes from
/// the stream (seed, generation, individual, purpose), so a run restored from
/// its checkpoint continues exactly like an uninterrupted one, with any
/// number of threads.
class Evolution {
public:
    Evolution(const runs::EvolveConfig& config, std::uint64_t seed, unsigned threads);

    /// Generation 0: initial_multiplier x mu perceptrons, evaluated and cut
    /// to mu by the same selection as every generation. Genome k is the seed
    /// k when set_seeds gave one (kept as it is, its genome stored whatever
    /// the retention), else random from the stream (seed, 0, k,
    /// initial_genome), as in an unseeded run.
    runs::GenerationWrite initialise();
    /// Seeds generation 0 (before initialise()): `seeds` (at most mu, their
    /// networks of the config's inputs and outputs) take the places of the
    /// first random genomes.
    void set_seeds(std::vector<nn::Genome> seeds);
    /// One epoch: mating selection, mutation (+ simplify), evaluation of the
    /// children, diversity on parents + children, (mu + lambda) selection.
    runs::GenerationWrite epoch();

    /// The state to resume from.
    nlohmann::json checkpoint() const;
    /// Restores the state written by checkpoint(); throws DataError if it is malformed.
    void restore(const nlohmann::json& state);

    /// Gives the run its knowledge base (config.kb set): `kb` as stored under
    /// `kb_id`, observed from now on as source `source_name`.
    void attach_kb(kb::KnowledgeBase kb, std::int64_t kb_id, const std::string& source_name);
    /// Shapes the reward with `kb` under `treatment` from now on: every
    /// evaluated policy's r_max is computed and recorded, and enters the
    /// objectives as the treatment says (exp/treatment.hpp).
    void attach_shaping(kb::KnowledgeBase kb, runs::Treatment treatment);
    /// Evaluates every generation from now on with `remote` (kept by the
    /// caller) instead of this process's threads; null: back to the threads.
    void set_remote(RemoteEvaluator* remote) { remote_ = remote; }
    /// The KB that shapes the reward, null without one.
    const kb::KnowledgeBase* shaping_kb() const { return shaping_kb_ ? &*shaping_kb_ : nullptr; }

    /// The run's knowledge base, null without one.
    const kb::KnowledgeBase* knowledge_base() const { return kb_ ? &*kb_ : nullptr; }

    int generation() const { return generation_; }
    const std::vector<Member>& population() const { return population_; }

private:
    runs::GenerationWrite select(std::vector<Member> mixed, std::size_t first_new, double started);
    /// A new member with the next id, counting its NaN outputs.
    Member make_member(nn::Genome genome, const Evaluation& evaluation, std::optional<std::int64_t> parent);
    /// Evaluates `genomes`; computes their r_max with a shaping KB; observes
    /// them into the run's KB when this generation is an observing one.
    std::vector<Evaluation> evaluate(const std::vector<nn::Genome>& genomes);

    runs::EvolveConfig config_;
    std::uint64_t seed_;
    unsigned threads_;
    std::shared_ptr<const sim::Task> task_;
    evo::DiversityMatrix diversity_;
    std::vector<Member> population_;
    std::vector<nn::Genome> seeds_;  // generation 0's first genomes, when seeded
    int generation_ = -1;
    std::int64_t next_id_ = 0;
    std::int64_t nan_outputs_ = 0;  // NaN outputs of the generation in progress
    std::optional<kb::KnowledgeBase> kb_;
    std::int64_t kb_id_ = 0;
    std::uint32_t kb_source_ = 0;
    std::optional<std::size_t> kb_previous_size_;  // set when the generation in progress observed
    std::optional<kb::KnowledgeBase> shaping_kb_;
    runs::Treatment treatment_ = runs::Treatment::none;
    double shaping_max_average_ = 0;  // the sum treatment's normaliser
    double time_simulation_ = 0;  // seconds of the generation in progress
    double time_kb_ = 0;
    RemoteEvaluator* remote_ = nullptr;
    /// The generation's behaviour matrices (tens of MB), kept from one generation to the next:
    /// a fresh buffer each time cost a quarter of a KB-observing generation in page faults.
    std::vector<float> behaviours_;
};

/// Options of `stepstone evolve`.
struct EvolveOptions {
    std::filesystem::path config_path;
    std::filesystem::path db_path;
    std::optional<std::uint64_t> seed;
    std::optional<int> generations;
    std::optional<runs::Retain> retain;
    std::optional<runs::Treatment> treatment;     ///< overrides transfer.treatment
    std::optional<std::filesystem::path> kb;      ///< overrides transfer.kb (the shaping KB file)
    std::optional<std::string> kb_name;           ///< overrides transfer.kb_name
    std::optional<std::filesystem::path> seed_from;  ///< overrides transfer.seed.from (the seed source run)
    std::optional<runs::SeedWith> seed_with;         ///< overrides transfer.seed.with
    std::optional<int> seed_count;                   ///< overrides transfer.seed.count
    unsigned threads = 0;  ///< 0 = every core
    /// Set on rank 0 of `evolve --mpi`: the ranks that evaluate each generation.
    MpiLeader* mpi = nullptr;
    /// False in a worker rank of `campaign --mpi`: SIGINT and SIGTERM are left
    /// to the MPI job (rank 0 names a lost rank) instead of stopping the run.
    bool stop_on_signals = true;
    bool resume = false;
    bool allow_config_change = false;
    bool force = false;
    ProgressMode progress = ProgressMode::automatic;
};

/// What a finished `evolve` reports.
struct EvolveSummary {
    std::uint64_t seed = 0;
    int generations_done = -1;
    double best_reward = 0;
    std::int64_t evaluations = 0;
    bool was_finished = false;  ///< --resume on a run that had nothing left to do
};

/// Creates (or resumes) a run file and evolves it to the asked generation,
/// one transaction per generation. With a transfer KB, the KB is loaded and
/// checked (channels and width against the task, randomized or not against
/// the treatment) before anything is written, and its content digest is
/// stored with the run's config; a resume with a different KB is refused.
/// Throws ConfigError on bad options, config or KB, DatabaseError on an
/// unusable file (left unchanged).
EvolveSummary run_evolve(const EvolveOptions& options);

/// Loads and checks the shaping KB of `config.transfer` (channels and width
/// against the task, randomized or not against the treatment, its digest
/// against transfer.kb_digest when set), then records its digest and name in
/// the config and makes its path absolute. Throws ConfigError naming the file.
kb::KnowledgeBase load_shaping_kb(runs::EvolveConfig& config);

}  // namespace stepstone::exp
