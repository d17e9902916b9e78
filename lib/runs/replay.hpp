#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "db/connection.hpp"
#include "runs/evolve_config.hpp"
#include "runs/run_store.hpp"
#include "sim/episode.hpp"

namespace stepstone::runs {

/// A stored genome re-simulated.
struct Replay {
    std::int64_t individual_id = 0;
    int generation = 0;         ///< generation in which it was evaluated
    double stored_reward = 0;   ///< the reward the run recorded
    sim::EpisodeResult result;  ///< the reward now
};

/// Re-simulates the genome of `individual` ("best" for the stored genome with
/// the highest reward, or an individual id) of the run in `db_path` (opened
/// read-only) with the run's own task and network settings. `observer` sees
/// every step. Throws ConfigError for an unparsable individual, DataError for
/// one with no stored genome, DatabaseError for an unusable file.
template <class Observer = sim::IgnoreSteps>
Replay replay(const std::filesystem::path& db_path, const std::string& individual, Observer&& observer = {});

/// The non-template part of replay(): loads the task, the network settings
/// and the genome. Implementation detail, public for the template.
struct ReplaySetup {
    std::shared_ptr<const sim::Task> task;
    struct Impl;
    std::shared_ptr<Impl> impl;
    Replay replay;
    /// Runs the episode with `observer` called after each step; `behaviour`,
    /// if not empty, receives the first start's behaviour matrix
    /// (task->behaviour_size() floats).
    sim::EpisodeResult run(const std::function<void(const sim::StepView&)>& observer,
                           std::span<float> behaviour = {});
};
ReplaySetup prepare_replay(const std::filesystem::path& db_path, const std::string& individual);
/// The same from a run file the caller has open, its run row and the run's
/// config already read (`config` is `run.config` parsed).
ReplaySetup prepare_replay(db::Connection& connection, const RunRecord& run, const EvolveConfig& config,
                           const std::string& individual);

/// The first start's behaviour matrix of a stored genome (rows = time steps,
/// sim::kChannels columns), with the replay facts in `replay` if not null.
std::vector<float> replay_behaviour(const std::filesystem::path& db_path, const std::string& individual,
                                    Replay* replay = nullptr);

template <class Observer>
Replay replay(const std::filesystem::path& db_path, const std::string& individual, Observer&& observer) {
    ReplaySetup setup = prepare_replay(db_path, individual);
    setup.replay.result = setup.run(std::forward<Observer>(observer));
    return setup.replay;
}

}  // namespace stepstone::runs
