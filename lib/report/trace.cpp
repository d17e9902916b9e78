// A stored policy replayed on one start, its segments looked up in a KB.

#include "report/trace.hpp"

#include <algorithm>

#include "core/error.hpp"
#include "core/text.hpp"
#include "db/database.hpp"
#include "kb/segments.hpp"
#include "runs/replay.hpp"
#include "runs/run_store.hpp"

namespace stepstone::report {

std::optional<kb::SegmentMatch> Trace::match_at(int step) const {
    if (!has_kb() || step < 0) return std::nullopt;
    const auto index = static_cast<std::size_t>(step) / segment_width;
    if (index >= segments.size()) return std::nullopt;
    return segments[index];
}

Trace trace_episode(const std::shared_ptr<const sim::Task>& task, const EpisodeRunner& run, int start,
                    const kb::KnowledgeBase* kb, const std::string& kb_name, const std::string& what) {
    const auto& config = task->config();
    if (start < 0 || start >= config.starts) {
        throw ConfigError(concat(option_name("start"), " must be within 1 to ", config.starts,
                                 " (the run's starts), got ", start + 1));
    }
    constexpr auto channels = static_cast<std::size_t>(sim::kChannels);
    Trace trace;
    trace.start = start;
    trace.task = task;
    trace.steps.reserve(static_cast<std::size_t>(config.steps_per_start));
    trace.behaviour.reserve(task->behaviour_size());
    const auto result = run([&](const sim::StepView& view) {
        if (view.start != start) return;
        trace.steps.push_back({view.step, view.pose.x, view.pose.y, view.pose.heading, view.carrying,
                               view.door_open, view.lit});
        trace.behaviour.insert(trace.behaviour.end(), view.inputs, view.inputs + sim::kInputs);
        trace.behaviour.insert(trace.behaviour.end(), view.outputs, view.outputs + sim::kOutputs);
    });
    if (trace.steps.empty()) {
        throw DataError(concat(what, " stood still too long (stand-still rule) before start ", start + 1));
    }
    // after an early stop the rows repeat the last one, as in a recorded behaviour
    while (trace.behaviour.size() < task->behaviour_size()) {
        trace.behaviour.insert(trace.behaviour.end(), trace.behaviour.end() - static_cast<long>(channels),
                               trace.behaviour.end());
    }
    trace.reward = result.reward;
    trace.balls = result.balls;
    if (kb != nullptr) {
        const auto& params = kb->params();
        if (params.channels != channels) {
            throw DataError(concat("knowledge base \"", kb_name, "\" has ", params.channels,
                                   " channels, the run's behaviours have ", channels));
        }
        if (params.segment_width > static_cast<std::size_t>(config.steps_per_start)) {
            throw DataError(concat("knowledge base \"", kb_name, "\" has segments of ", params.segment_width,
                                   " steps, longer than the run's start (", config.steps_per_start, " steps)"));
        }
        const auto lookup = kb->lookup(kb::segment_behaviour(trace.behaviour, channels, params.segment_width));
        trace.kb_name = kb_name;
        trace.segment_width = params.segment_width;
        trace.max_average = kb->max_average();
        trace.r_max = lookup.r_max;
        trace.segments = lookup.segments;
    }
    return trace;
}

namespace {

Trace trace_replay(runs::ReplaySetup setup, const std::filesystem::path& run_db, int start,
                   const kb::KnowledgeBase* kb, const std::string& kb_name) {
    auto trace = trace_episode(
        setup.task, [&](const auto& observer) { return setup.run(observer); }, start, kb, kb_name,
        concat(run_db.filename().string(), ": individual ", setup.replay.individual_id));
    trace.individual_id = setup.replay.individual_id;
    trace.generation = setup.replay.generation;
    trace.stored_reward = setup.replay.stored_reward;
    return trace;
}

}  // namespace

Trace trace_policy(const std::filesystem::path& run_db, const std::string& individual, int start,
                   const kb::KnowledgeBase* kb, const std::string& kb_name) {
    return trace_replay(runs::prepare_replay(run_db, individual), run_db, start, kb, kb_name);
}

Trace trace_policy(db::Connection& connection, const runs::RunRecord& run, const runs::EvolveConfig& config,
                   const std::string& individual, int start, const kb::KnowledgeBase* kb,
                   const std::string& kb_name) {
    return trace_replay(runs::prepare_replay(connection, run, config, individual), connection.name(), start,
                        kb, kb_name);
}

std::optional<db::StoredKb> figure_kb(const std::filesystem::path& run_db, const std::filesystem::path& kb_file,
                                      const std::string& kb_name) {
    if (!kb_file.empty()) {
        auto connection = db::open_database(kb_file, db::OpenMode::read_only);
        return db::load_kb(connection, kb_name);
    }
    auto connection = db::open_database(run_db, db::OpenMode::read_only);
    return run_kb(connection);
}

std::optional<db::StoredKb> run_kb(db::Connection& run) {
    for (const auto& summary : db::list_kbs(run)) {
        if (summary.name == runs::kRunKbName) return db::load_kb(run, runs::kRunKbName);
    }
    return std::nullopt;
}

}  // namespace stepstone::report
