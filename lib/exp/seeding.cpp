#include "exp/seeding.hpp"

#include <algorithm>
#include <filesystem>

#include "core/error.hpp"
#include "core/text.hpp"
#include "db/database.hpp"
#include "db/digest.hpp"
#include "evo/pareto.hpp"
#include "runs/run_store.hpp"

namespace stepstone::exp {

namespace fs = std::filesystem;

namespace {

// one policy the source offers
struct Candidate {
    std::int64_t id = 0;
    double reward = 0;
    nlohmann::json genome;
};

void check_digest(const std::string& file, const runs::SeedConfig& seed, const std::string& digest) {
    if (!seed.digest.empty() && seed.digest != digest) {
        throw ConfigError(concat(file, ": the seed source's digest is ", digest,
                                 ", the run was seeded from a run of digest ", seed.digest,
                                 " (a different source run)"));
    }
}

// the inputs and outputs of the source's networks, as its stored config gives them
void check_network(const std::string& file, const runs::RunRecord& source, const runs::EvolveConfig& config) {
    const auto dnn = source.config.value("dnn", nlohmann::json::object());
    const int inputs = dnn.value("inputs", config.dnn.inputs);
    const int outputs = dnn.value("outputs", config.dnn.outputs);
    if (inputs != config.dnn.inputs || outputs != config.dnn.outputs) {
        throw ConfigError(concat(file, ": the source run's networks have ", inputs, " inputs and ", outputs,
                                 " outputs (", inputs + outputs, " behaviour channels), this run's ",
                                 config.dnn.inputs, " and ", config.dnn.outputs, " (",
                                 config.dnn.inputs + config.dnn.outputs, ")"));
    }
}

// the latest checkpoint's population, or its members that no other dominates
std::vector<Candidate> checkpoint_candidates(db::Connection& connection, const std::string& file,
                                             const runs::RunRecord& source, const runs::EvolveConfig& config,
                                             runs::SeedWith with) {
    const auto checkpoint = runs::load_checkpoint(connection, source.id);
    if (!checkpoint) throw DataError(concat(file, ": the source run has no committed generation"));
    std::vector<Candidate> population;
    evo::Objectives objectives;
    try {
        for (const auto& member : checkpoint->at("population")) {
            population.push_back({member.at("id").get<std::int64_t>(), member.at("reward").get<double>(),
                                  member.at("genome")});
            objectives.push_back(member.at("objectives").get<std::vector<double>>());
        }
    } catch (const nlohmann::json::exception& e) {
        throw DatabaseError(
            concat(file, ": the source run has a malformed checkpoint: ", one_line(e.what())));
    }
    if (population.empty())
        throw DataError(concat(file, ": the source run's checkpoint holds no population"));
    if (with == runs::SeedWith::population) {
        if (population.size() != static_cast<std::size_t>(config.ea.population_size)) {
            throw ConfigError(concat(file, ": the source population holds ", population.size(),
                                     " policies, this run's ea.population_size is ",
                                     config.ea.population_size,
                                     " (seed with front or best, or give both runs one population size)"));
        }
        return population;
    }
    const auto fronts = evo::non_dominated_fronts(objectives);
    std::vector<Candidate> front;
    for (std::size_t k : fronts.front()) front.push_back(population[k]);
    return front;
}

}  // namespace

Seeds load_seeds(runs::EvolveConfig& config) {
    runs::SeedConfig& seed = *config.transfer->seed;
    const std::string file = seed.from.string();
    if (!fs::exists(seed.from)) {
        throw DatabaseError(concat(file, ": no such file (the seed source, ", option_name("seed_from"),
                                   " or transfer.seed.from)"));
    }
    db::Connection connection = db::open_database(seed.from, db::OpenMode::read_only);
    const runs::RunRecord source = runs::load_run(connection);
    if (source.status != runs::RunStatus::finished) {
        throw ConfigError(concat(file, ": the source run is not finished (", to_string(source.status),
                                 ", generation ", source.generations_done, " of ", source.generations,
                                 "); seed from a finished run"));
    }
    check_network(file, source, config);
    const std::string digest = db::run_digest(connection);
    check_digest(file, seed, digest);

    const auto limit = static_cast<std::size_t>(std::min(seed.count, config.ea.population_size));
    std::vector<Candidate> candidates;
    if (seed.with == runs::SeedWith::best) {
        for (auto& stored : runs::load_best_genomes(connection, source.id, static_cast<std::int64_t>(limit)))
            candidates.push_back({stored.individual_id, stored.reward, std::move(stored.genome)});
    } else {
        candidates = checkpoint_candidates(connection, file, source, config, seed.with);
    }
    // highest task reward first, the lower source id on ties (the SQL of best orders alike)
    std::stable_sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) {
        return a.reward > b.reward || (a.reward == b.reward && a.id < b.id);
    });
    if (candidates.size() > limit) candidates.resize(limit);

    Seeds seeds;
    for (const auto& candidate : candidates) {
        nn::Genome genome = [&] {
            try {
                return nn::Genome::from_json(candidate.genome);
            } catch (const Error& e) {
                throw DataError(concat(file, ": the genome of individual ", candidate.id,
                                       " is unreadable: ", one_line(e.what())));
            }
        }();
        if (genome.input_count() != static_cast<std::size_t>(config.dnn.inputs) ||
            genome.output_count() != static_cast<std::size_t>(config.dnn.outputs)) {
            throw ConfigError(concat(file, ": individual ", candidate.id, "'s network has ",
                                     genome.input_count(), " inputs and ", genome.output_count(),
                                     " outputs, this run's ", config.dnn.inputs, " and ",
                                     config.dnn.outputs));
        }
        seeds.genomes.push_back(std::move(genome));
        seeds.source_ids.push_back(candidate.id);
    }
    seed.digest = digest;
    seed.from = fs::absolute(seed.from).lexically_normal();
    return seeds;
}

void check_seed_source(runs::EvolveConfig& config) {
    runs::SeedConfig& seed = *config.transfer->seed;
    if (fs::exists(seed.from)) {
        const std::string file = seed.from.string();
        db::Connection connection = db::open_database(seed.from, db::OpenMode::read_only);
        const std::string digest = db::run_digest(connection);
        check_digest(file, seed, digest);
        seed.digest = digest;
    }
    seed.from = fs::absolute(seed.from).lexically_normal();
}

}  // namespace stepstone::exp
