#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "db/kb_store.hpp"
#include "kb/knowledge_base.hpp"
#include "runs/evolve_config.hpp"
#include "runs/run_store.hpp"
#include "sim/episode.hpp"
#include "sim/task.hpp"

namespace stepstone::report {

/// One simulated step of a traced start.
struct TraceStep {
    int step = 0;         ///< step within the start
    double x = 0.0, y = 0.0, heading = 0.0;  ///< pose at which the step's inputs were sensed
    bool carrying = false;  ///< after the step's action
    bool door_open = false; ///< after the step's action
    std::uint32_t lit = 0;  ///< lights lit after the step's action (bit i: Task::lights()[i])
};

/// A stored policy replayed on one start, with its segments' KB matches.
struct Trace {
    std::int64_t individual_id = 0;
    int generation = 0;
    double stored_reward = 0.0;
    double reward = 0.0;  ///< of the whole replayed evaluation (every start)
    int balls = 0;        ///< scored over every start
    int start = 0;        ///< 0-based start index
    std::shared_ptr<const sim::Task> task;
    std::vector<TraceStep> steps;  ///< every step the start ran, in order
    /// Behaviour matrix of the start (steps_per_start rows x sim::kChannels),
    /// rows after an early stop repeating the last one, as evolve records it.
    std::vector<float> behaviour;
    // set when a knowledge base was given
    std::string kb_name;
    std::size_t segment_width = 0;  ///< 0 without a KB
    double max_average = 0.0;       ///< the KB's largest average (the colour scale's top)
    double r_max = 0.0;
    std::vector<kb::SegmentMatch> segments;  ///< segment i covers steps [i w, (i + 1) w)

    bool has_kb() const { return segment_width > 0; }
    /// The match of the segment holding `step`, nullopt without a KB or past the last whole segment.
    std::optional<kb::SegmentMatch> match_at(int step) const;
};

/// Replays `individual` ("best" or an id) of the run in `run_db` with the
/// run's stored settings and records start `start` (0-based). With `kb`, each
/// whole segment of that start's behaviour is looked up under the KB's rule
/// (the paper looks up the first start only; other starts are segmented the
/// same way). Throws ConfigError for a start outside the task's, DataError
/// when the evaluation stopped (stand-still rule) before that start, or the
/// KB does not fit the behaviour (channels, width), DatabaseError for an
/// unusable file.
Trace trace_policy(const std::filesystem::path& run_db, const std::string& individual, int start,
                   const kb::KnowledgeBase* kb, const std::string& kb_name = "");
/// The same from a run file the caller has open, with its run row and config
/// already read.
Trace trace_policy(db::Connection& connection, const runs::RunRecord& run, const runs::EvolveConfig& config,
                   const std::string& individual, int start, const kb::KnowledgeBase* kb,
                   const std::string& kb_name = "");

/// Runs one evaluation: calls the observer after every step, returns the result.
using EpisodeRunner = std::function<sim::EpisodeResult(const std::function<void(const sim::StepView&)>&)>;

/// The core of trace_policy for any controller: `run` evaluates it on `task`.
/// `what` names the policy in errors. The replay facts (individual, rewards
/// stored) are left for the caller.
Trace trace_episode(const std::shared_ptr<const sim::Task>& task, const EpisodeRunner& run, int start,
                    const kb::KnowledgeBase* kb, const std::string& kb_name, const std::string& what);

/// The KB a figure of `run_db` is coloured by: the only KB of `kb_file` (or
/// the one called `kb_name`) when `kb_file` is given, else the run's own KB
/// when it built one, else none. Files are opened read-only.
std::optional<db::StoredKb> figure_kb(const std::filesystem::path& run_db, const std::filesystem::path& kb_file,
                                      const std::string& kb_name = "");
/// The run's own KB, read from its open file, when it built one.
std::optional<db::StoredKb> run_kb(db::Connection& run);

}  // namespace stepstone::report
