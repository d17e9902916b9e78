#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string_view>
#include <vector>

#include "core/portable_math.hpp"
#include "sim/arena.hpp"
#include "sim/arena_spec.hpp"
#include "sim/robot.hpp"
#include "sim/sensors.hpp"
#include "sim/units.hpp"

namespace stepstone::sim {

/// The two tasks of the paper: source (balls, a switch opening a door) and
/// target (door open, the switch spawns one ball; collectball's VARIANT_SW2).
enum class TaskKind { source, target };

/// "source" or "target".
std::string_view to_string(TaskKind kind);
/// Parses "source" or "target"; throws ConfigError naming `what` otherwise.
TaskKind parse_task_kind(std::string_view text, std::string_view what = "task");

/// Steps after a press before the target task's switch is lit again.
inline constexpr int kSwitchRearmSteps = 100;

/// Settings of one evaluation. Defaults are the paper's values.
struct TaskConfig {
    TaskKind kind = TaskKind::source;
    int steps_per_start = 4000;  ///< steps of each start
    int starts = 3;              ///< number of starts, 1 to 3 (the three start poses, in order)
    int still_limit = 100;       ///< the evaluation ends when the cumulative still steps exceed this
    int grid_period = 50;        ///< steps between two diversity-grid samples of the first start
    /// The arena (walls, door, balls, switch, basket, start poses); null: the paper's.
    std::shared_ptr<const ArenaSpec> arena{};
    /// The sine and cosine of the odometry and sensors (set from a run config's "math"):
    /// stepstone's own by default, one answer on every machine (core/portable_math.hpp).
    Math math = Math::portable;

    /// The arena, the paper's when none is set.
    const ArenaSpec& arena_spec() const { return arena ? *arena : paper_arena(); }

    /// Throws ConfigError naming the first field out of range (the arena's included).
    void validate() const;
};

/// Immutable description of a task: arena, lights, start poses and rules.
/// Shared read-only by any number of threads; episodes keep their own state.
class Task {
public:
    /// Use make_task(); public for make_shared.
    Task(const TaskConfig& config, std::vector<Light> lights, std::uint32_t initial_lit, bool door_starts_open,
         int switch_index, int spawn_ball_index);

    /// The arena's description (the paper's unless the config names one).
    const ArenaSpec& arena_spec() const { return config_.arena_spec(); }
    /// The basket: releases within its disc score.
    const Basket& basket() const { return arena_spec().basket; }

    const TaskConfig& config() const { return config_; }
    TaskKind kind() const { return config_.kind; }
    const Arena& arena() const { return arena_; }
    /// Lights in index order: balls first, then basket lights, then the switch.
    std::span<const Light> lights() const { return lights_; }
    /// Precomputed sight-line candidates of the lights (the sensors' hot path).
    const SightTable& sight() const { return sight_; }
    /// Lights on at each start (bit i = light i).
    std::uint32_t initial_lit() const { return initial_lit_; }
    /// True when the door is open for the whole evaluation (target task).
    bool door_starts_open() const { return door_starts_open_; }
    /// Index of the switch in lights().
    int switch_index() const { return switch_index_; }
    /// Ball lit by a switch press (target task), or -1 (source task: the press opens the door).
    int spawn_ball_index() const { return spawn_ball_index_; }
    /// Start pose of start `index` (0-2): the arena's (the paper's: docs/original.md, objects).
    const Pose& start_pose(int index) const { return start_poses_[static_cast<std::size_t>(index)]; }

    /// Floats in a behaviour matrix: steps_per_start x kChannels.
    std::size_t behaviour_size() const;
    /// Cells in a diversity trajectory: ceil(steps_per_start / grid_period) (80 by default).
    std::size_t cell_count() const;
    /// Divisor of the reward: the arena's balls x starts (8 x 3 = 24 by default, in both
    /// tasks: the target task's one ball keeps the source's divisor, as the original).
    int reward_divisor() const { return static_cast<int>(arena_spec().balls.size()) * config_.starts; }

private:
    TaskConfig config_;
    Arena arena_;
    std::vector<Light> lights_;
    SightTable sight_;
    std::uint32_t initial_lit_;
    bool door_starts_open_;
    int switch_index_;
    int spawn_ball_index_;
    std::array<Pose, 3> start_poses_;
};

/// Builds the task described by `config` (validated first; throws ConfigError).
/// Source and target are defined once, in sim/tasks/.
std::shared_ptr<const Task> make_task(const TaskConfig& config);

}  // namespace stepstone::sim
