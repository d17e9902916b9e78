#include "exp/evolution.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <numeric>

#include "core/assert.hpp"
#include "core/error.hpp"
#include "core/rng.hpp"
#include "core/text.hpp"
#include "core/version.hpp"
#include "db/database.hpp"
#include "db/digest.hpp"
#include "db/kb_store.hpp"
#include "evo/pareto.hpp"
#include "evo/selection.hpp"
#include "exp/mpi_evolve.hpp"
#include "exp/parallel/writer_lock.hpp"
#include "kb/segments.hpp"
#include "nn/mutation.hpp"
#include "stats/summary.hpp"

namespace stepstone::exp {

namespace {

nlohmann::json cells_to_json(const evo::Trajectory& cells) {
    auto out = nlohmann::json::array();
    for (const auto& cell : cells) out.push_back({cell.x, cell.y});
    return out;
}

// ---------------------------------------------------------------- checkpoint

nlohmann::json member_to_json(const Member& m) {
    nlohmann::json json;
    json["id"] = m.id;
    json["parent_id"] = m.parent_id ? nlohmann::json(*m.parent_id) : nlohmann::json();
    json["genome"] = m.genome.to_json();
    json["reward"] = m.reward;
    json["balls"] = m.balls;
    json["steps"] = m.steps;
    json["cells"] = cells_to_json(m.cells);
    if (m.r_max) json["r_max"] = *m.r_max;
    json["objectives"] = m.objectives;
    json["crowding"] = m.crowding;
    return json;
}

Member member_from_json(const nlohmann::json& json) {
    Member m;
    m.id = json.at("id").get<std::int64_t>();
    if (!json.at("parent_id").is_null()) m.parent_id = json.at("parent_id").get<std::int64_t>();
    m.genome = nn::Genome::from_json(json.at("genome"));
    m.reward = json.at("reward").get<double>();
    m.balls = json.at("balls").get<int>();
    m.steps = json.at("steps").get<long>();
    for (const auto& cell : json.at("cells")) {
        m.cells.push_back({cell.at(0).get<std::int16_t>(), cell.at(1).get<std::int16_t>()});
    }
    if (json.contains("r_max")) m.r_max = json.at("r_max").get<double>();
    m.objectives = json.at("objectives").get<std::vector<double>>();
    m.crowding = json.at("crowding").get<double>();
    return m;
}

}  // namespace

// ----------------------------------------------------------------- Evolution

double shaped_r_max(const kb::KnowledgeBase& kb, std::span<const float> behaviour) {
    return kb.r_max(kb::segment_behaviour(behaviour, sim::kChannels, kb.params().segment_width));
}

Evolution::Evolution(const runs::EvolveConfig& config, std::uint64_t seed, unsigned threads)
    : config_(config), seed_(seed), threads_(resolve_threads(threads)), task_(sim::make_task(config.task)) {}

runs::GenerationWrite Evolution::initialise() {
    const double started = now_seconds();
    generation_ = 0;
    const auto count = static_cast<std::size_t>(config_.ea.initial_multiplier * config_.ea.population_size);
    std::vector<Member> mixed(count);
    std::vector<nn::Genome> genomes;
    genomes.reserve(count);
    for (std::size_t k = 0; k < count; ++k) {
        if (k < seeds_.size()) {
            genomes.push_back(seeds_[k]);  // a source run's policy, as it was stored there
            continue;
        }
        Rng rng(seed_, 0, k, Purpose::initial_genome);
        genomes.push_back(nn::Genome::random_perceptron(config_.dnn, rng));
        genomes.back().simplify();
    }
    const auto evaluations = evaluate(genomes);
    for (std::size_t k = 0; k < count; ++k) mixed[k] = make_member(std::move(genomes[k]), evaluations[k], std::nullopt);
    return select(std::move(mixed), 0, started);
}

runs::GenerationWrite Evolution::epoch() {
    const double started = now_seconds();
    ++generation_;
    const auto g = static_cast<std::uint64_t>(generation_);

    // mating selection on the current parents (docs/original.md: NSGA-II)
    evo::Objectives objectives;
    std::vector<double> crowding;
    for (const auto& m : population_) {
        objectives.push_back(m.objectives);
        crowding.push_back(m.crowding);
    }
    Rng selection_rng(seed_, g, 0, Purpose::selection);
    const auto parents = evo::select_parents(objectives, crowding, selection_rng);

    // children: mutated copies, simplified on the genotype as collectball does
    std::vector<nn::Genome> genomes;
    genomes.reserve(parents.size());
    for (std::size_t k = 0; k < parents.size(); ++k) {
        nn::Genome child = population_[parents[k]].genome;
        Rng rng(seed_, g, k, Purpose::mutation);
        nn::mutate(child, config_.dnn, rng);
        child.simplify();
        genomes.push_back(std::move(child));
    }
    const auto evaluations = evaluate(genomes);

    std::vector<Member> mixed = population_;
    const std::size_t first_new = mixed.size();
    for (std::size_t k = 0; k < genomes.size(); ++k) {
        mixed.push_back(make_member(std::move(genomes[k]), evaluations[k], population_[parents[k]].id));
    }
    return select(std::move(mixed), first_new, started);
}

void Evolution::set_seeds(std::vector<nn::Genome> seeds) {
    STEPSTONE_ASSERT(generation_ < 0 && seeds.size() <= static_cast<std::size_t>(config_.ea.population_size));
    seeds_ = std::move(seeds);
}

Member Evolution::make_member(nn::Genome genome, const Evaluation& evaluation, std::optional<std::int64_t> parent) {
    Member m;
    m.id = next_id_++;
    m.parent_id = parent;
    m.genome = std::move(genome);
    m.reward = evaluation.reward;
    m.balls = evaluation.balls;
    m.steps = evaluation.steps;
    m.milestones = evaluation.milestones;
    m.cells = evaluation.cells;
    m.r_max = evaluation.r_max;
    nan_outputs_ += evaluation.nan_outputs;
    return m;
}

void Evolution::attach_kb(kb::KnowledgeBase kb, std::int64_t kb_id, const std::string& source_name) {
    kb_ = std::move(kb);
    kb_id_ = kb_id;
    kb_source_ = kb_->add_source(source_name);
}

void Evolution::attach_shaping(kb::KnowledgeBase kb, runs::Treatment treatment) {
    shaping_max_average_ = kb.max_average();
    shaping_kb_ = std::move(kb);
    treatment_ = treatment;
}

std::vector<Evaluation> Evolution::evaluate(const std::vector<nn::Genome>& genomes) {
    kb_previous_size_.reset();
    const bool observe = kb_ && generation_ % config_.kb->period == 0;
    const bool shape = shaping_kb_.has_value();
    const double started = now_seconds();
    std::vector<float>& behaviours = behaviours_;
    const std::size_t width = task_->behaviour_size();
    std::vector<Evaluation> evaluations;
    if (remote_) {
        // simulation and lookups elsewhere: their time counts as simulation
        evaluations = remote_->evaluate(genomes, observe ? &behaviours : nullptr);
        time_simulation_ = now_seconds() - started;
    } else {
        evaluations =
            evaluate_all(*task_, genomes, config_.dnn, threads_, observe || shape ? &behaviours : nullptr);
        time_simulation_ = now_seconds() - started;
        if (shape) {
            // lookups only read the KB: each policy's r_max goes to its own slot
            parallel_for(genomes.size(), threads_, [&](std::size_t k) {
                evaluations[k].r_max =
                    shaped_r_max(*shaping_kb_, std::span<const float>(behaviours.data() + k * width, width));
            });
        }
    }
    time_kb_ = now_seconds() - started - time_simulation_;
    if (!observe) return evaluations;

    // every policy of an observing generation, in index order, segment by segment
    kb_previous_size_ = kb_->size();
    for (std::size_t k = 0; k < genomes.size(); ++k) {
        const std::span<const float> behaviour(behaviours.data() + k * width, width);
        const auto segments = kb::segment_behaviour(behaviour, sim::kChannels,
                                                    static_cast<std::size_t>(config_.kb->segment_width));
        kb_->observe(segments, evaluations[k].reward, {kb_source_, generation_});
    }
    time_kb_ = now_seconds() - started - time_simulation_;
    return evaluations;
}

runs::GenerationWrite Evolution::select(std::vector<Member> mixed, std::size_t first_new, double started) {
    // diversity of every member of the mixed population (docs/original.md: diversity),
    // reusing the distances between members already seen
    std::vector<std::uint64_t> ids;
    std::vector<evo::Trajectory> trajectories;
    for (const auto& m : mixed) {
        ids.push_back(static_cast<std::uint64_t>(m.id));
        trajectories.push_back(m.cells);
    }
    const double diversity_started = now_seconds();
    if (remote_) {
        // the ranks that evaluated the generation share its distances too
        diversity_.update(
            ids, trajectories,
            [this](std::span<const evo::PositionPair> pairs, std::span<const evo::Trajectory> all,
                   std::size_t length) { return remote_->distances(pairs, all, length); });
    } else {
        diversity_.update(ids, trajectories, threads_);
    }
    const auto sums = diversity_.sums();
    const double selection_started = now_seconds();
    evo::Objectives objectives;
    const double ball_reward = 1.0 / task_->reward_divisor();
    for (std::size_t k = 0; k < mixed.size(); ++k) {
        objectives.push_back(treatment_objectives(treatment_, mixed[k].reward, sums[k], mixed[k].r_max,
                                                  shaping_max_average_, ball_reward));
    }

    const auto ranking = evo::rank_and_crowd(objectives);
    const auto kept = evo::survivors(objectives, static_cast<std::size_t>(config_.ea.population_size));
    const double selection_done = now_seconds();

    runs::GenerationWrite write;
    auto& stats = write.stats;
    stats.generation = generation_;
    stats.evaluations = static_cast<std::int64_t>(mixed.size() - first_new);
    for (const auto& front : ranking.fronts) stats.front_sizes.push_back(front.size());
    stats.diversity_min = *std::min_element(sums.begin(), sums.end());
    stats.diversity_max = *std::max_element(sums.begin(), sums.end());

    // rows of the individuals evaluated in this generation
    for (std::size_t k = first_new; k < mixed.size(); ++k) {
        const Member& m = mixed[k];
        runs::IndividualRow row;
        row.id = m.id;
        row.generation = generation_;
        row.parent_id = m.parent_id;
        row.reward = m.reward;
        row.fitness = objectives[k][0];
        row.diversity = objectives[k][1];
        row.r_max = m.r_max;
        row.balls = m.balls;
        row.steps = m.steps;
        row.milestones = m.milestones;
        write.individuals.push_back(row);
    }

    // genomes kept for replay: the first front, the best reward (lowest id on ties), or all new ones
    std::size_t best = 0;
    for (std::size_t k = 1; k < mixed.size(); ++k) {
        if (mixed[k].reward > mixed[best].reward ||
            (mixed[k].reward == mixed[best].reward && mixed[k].id < mixed[best].id)) {
            best = k;
        }
    }
    std::vector<std::size_t> stored(ranking.fronts.front().begin(), ranking.fronts.front().end());
    stored.push_back(best);
    if (generation_ == 0) {
        // a seeded run keeps the policies it started from
        for (std::size_t k = 0; k < seeds_.size(); ++k) stored.push_back(k);
    }
    if (config_.retain == runs::Retain::all) {
        for (std::size_t k = first_new; k < mixed.size(); ++k) stored.push_back(k);
    }
    std::sort(stored.begin(), stored.end());
    stored.erase(std::unique(stored.begin(), stored.end()), stored.end());
    for (std::size_t k : stored) write.genomes.push_back({mixed[k].id, mixed[k].genome.to_json().dump()});

    // the survivors become the population
    std::vector<Member> next;
    next.reserve(kept.indices.size());
    for (std::size_t j = 0; j < kept.indices.size(); ++j) {
        Member m = std::move(mixed[kept.indices[j]]);
        m.objectives = objectives[kept.indices[j]];
        m.crowding = kept.crowding[j];
        next.push_back(std::move(m));
    }
    population_ = std::move(next);

    std::vector<double> rewards;
    for (const auto& m : population_) rewards.push_back(m.reward);
    stats.best_reward = *std::max_element(rewards.begin(), rewards.end());
    stats.mean_reward = std::accumulate(rewards.begin(), rewards.end(), 0.0) / static_cast<double>(rewards.size());
    stats.median_reward = stats::median(rewards);
    stats.wall_time = now_seconds() - started;
    stats.time_simulation = time_simulation_;
    stats.time_kb = time_kb_;
    stats.time_diversity = selection_started - diversity_started;
    stats.time_selection = selection_done - selection_started;
    write.nan_outputs = nan_outputs_;
    nan_outputs_ = 0;
    if (kb_previous_size_) {
        write.kb = &*kb_;
        write.kb_id = kb_id_;
        write.kb_previous_size = *kb_previous_size_;
    }
    write.checkpoint = checkpoint();
    return write;
}

nlohmann::json Evolution::checkpoint() const {
    nlohmann::json state;
    state["generation"] = generation_;
    state["next_id"] = next_id_;
    state["population"] = nlohmann::json::array();
    for (const auto& m : population_) state["population"].push_back(member_to_json(m));
    return state;
}

void Evolution::restore(const nlohmann::json& state) {
    try {
        generation_ = state.at("generation").get<int>();
        next_id_ = state.at("next_id").get<std::int64_t>();
        std::vector<Member> population;
        for (const auto& member : state.at("population")) population.push_back(member_from_json(member));
        if (population.size() != static_cast<std::size_t>(config_.ea.population_size)) {
            throw DataError(concat("checkpoint holds ", population.size(), " individuals, the config asks for ",
                                   config_.ea.population_size));
        }
        population_ = std::move(population);
    } catch (const nlohmann::json::exception& e) {
        throw DataError(concat("checkpoint is malformed: ", one_line(e.what())));
    }
    diversity_.clear();
}

}  // namespace stepstone::exp
