#include "runs/replay.hpp"

#include <charconv>

#include "core/error.hpp"
#include "core/text.hpp"
#include "db/database.hpp"
#include "nn/network.hpp"
#include "runs/evolve_config.hpp"
#include "runs/run_store.hpp"

namespace stepstone::runs {

struct ReplaySetup::Impl {
    nn::Network network;
};

ReplaySetup prepare_replay(const std::filesystem::path& db_path, const std::string& individual) {
    auto connection = db::open_database(db_path, db::OpenMode::read_only);
    const RunRecord run = load_run(connection);
    // the stored config names every value, so no default of this program enters the replay
    const EvolveConfig config =
        EvolveConfig::from_json(run.config, db_path.string() + " (stored config)", {}, ConfigOrigin::stored);
    return prepare_replay(connection, run, config, individual);
}

ReplaySetup prepare_replay(db::Connection& connection, const RunRecord& run, const EvolveConfig& config,
                           const std::string& individual) {
    StoredGenome stored;
    if (individual == "best") {
        stored = load_best_genome(connection, run.id);
    } else {
        std::int64_t id = -1;
        const auto* end = individual.data() + individual.size();
        const auto parsed = std::from_chars(individual.data(), end, id);
        if (parsed.ec != std::errc() || parsed.ptr != end || id < 0) {
            throw ConfigError(
                concat("individual must be 'best' or an individual id, got \"", individual, '"'));
        }
        stored = load_genome(connection, run.id, id);
    }

    ReplaySetup setup;
    setup.task = sim::make_task(config.task);
    setup.impl = std::make_shared<ReplaySetup::Impl>();
    setup.impl->network = nn::Network(nn::Genome::from_json(stored.genome), config.dnn);
    setup.replay.individual_id = stored.individual_id;
    setup.replay.generation = stored.generation;
    setup.replay.stored_reward = stored.reward;
    return setup;
}

sim::EpisodeResult ReplaySetup::run(const std::function<void(const sim::StepView&)>& observer,
                                    std::span<float> behaviour) {
    sim::Recording recording;
    recording.behaviour = behaviour;
    return sim::run_episode(*task, impl->network, recording, observer);
}

std::vector<float> replay_behaviour(const std::filesystem::path& db_path, const std::string& individual,
                                    Replay* replay) {
    ReplaySetup setup = prepare_replay(db_path, individual);
    std::vector<float> behaviour(setup.task->behaviour_size());
    setup.replay.result = setup.run(sim::IgnoreSteps{}, behaviour);
    if (replay) *replay = setup.replay;
    return behaviour;
}

}  // namespace stepstone::runs
