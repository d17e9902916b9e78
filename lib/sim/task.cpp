#include "sim/task.hpp"

#include "core/error.hpp"
#include "core/text.hpp"
#include "sim/tasks/tasks.hpp"
#include "sim/units.hpp"

namespace stepstone::sim {

std::string_view to_string(TaskKind kind) { return kind == TaskKind::source ? "source" : "target"; }

TaskKind parse_task_kind(std::string_view text, std::string_view what) {
    if (text == "source") return TaskKind::source;
    if (text == "target") return TaskKind::target;
    throw ConfigError(concat(what, " must be source or target, got '", text, "'"));
}

void TaskConfig::validate() const {
    if (steps_per_start < 1 || steps_per_start > 10'000'000) {
        throw ConfigError(concat("steps_per_start must be in [1, 10000000], got ", steps_per_start));
    }
    if (starts < 1 || starts > 3) throw ConfigError(concat("starts must be in [1, 3], got ", starts));
    if (still_limit < 0) throw ConfigError(concat("still_limit must be >= 0, got ", still_limit));
    if (grid_period < 1) throw ConfigError(concat("grid_period must be >= 1, got ", grid_period));
    if (arena) arena->validate();
}

Task::Task(const TaskConfig& config, std::vector<Light> lights, std::uint32_t initial_lit,
           bool door_starts_open, int switch_index, int spawn_ball_index)
    : config_(config),
      arena_(config.arena_spec()),
      lights_(std::move(lights)),
      sight_(arena_, lights_),
      initial_lit_(initial_lit),
      door_starts_open_(door_starts_open),
      switch_index_(switch_index),
      spawn_ball_index_(spawn_ball_index),
      start_poses_(config.arena_spec().starts) {}

std::size_t Task::behaviour_size() const {
    return static_cast<std::size_t>(config_.steps_per_start) * static_cast<std::size_t>(kChannels);
}

std::size_t Task::cell_count() const {
    return static_cast<std::size_t>((config_.steps_per_start + config_.grid_period - 1) / config_.grid_period);
}

std::shared_ptr<const Task> make_task(const TaskConfig& config) {
    config.validate();
    return config.kind == TaskKind::source ? tasks::make_source_task(config) : tasks::make_target_task(config);
}

}  // namespace stepstone::sim
