#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "core/assert.hpp"
#include "sim/cos_sin.hpp"
#include "sim/robot.hpp"
#include "sim/sensors.hpp"
#include "sim/task.hpp"

namespace stepstone::sim {

/// One sample of the full pose trace: the pose at which a step's inputs were sensed.
struct PoseSample {
    int start = 0;
    int step = 0;  ///< step within the start
    double x = 0.0;
    double y = 0.0;
    double heading = 0.0;
};

/// Caller-owned buffers an episode writes into. Any of them may be empty or
/// null: that record is then not kept. Sizes are checked once per episode.
struct Recording {
    /// Behaviour matrix of the first start, row-major: steps_per_start rows
    /// (time steps) x kChannels columns (12 inputs then the 3 clamped outputs),
    /// size Task::behaviour_size(). Rows after an early stop repeat the last row.
    std::span<float> behaviour;
    /// Diversity trajectory of the first start: one (x, y) grid cell every
    /// grid_period steps, (int)(x * 12 / 600), (int)(y * 12 / 600), size
    /// Task::cell_count(). Slots after an early stop hold the final cell.
    std::span<std::array<int, 2>> cells;
    /// Full trace, appended to (one sample per step run). Reserve
    /// starts x steps_per_start samples to avoid allocating during the episode.
    std::vector<PoseSample>* trace = nullptr;
};

/// The steps of the task an evaluation reached, summed over its starts
/// (docs/simulator.md: milestones). Balls collected are EpisodeResult::balls.
struct Milestones {
    int presses = 0;          ///< grabs at the lit switch (source: door opens; target: ball lit)
    int pickups = 0;          ///< balls taken (a grab within reach of a lit ball)
    long carry_steps = 0;     ///< steps whose action leaves the robot carrying a ball
    int basket_releases = 0;  ///< releases with the centre within the basket radius, scoring or not

    bool operator==(const Milestones&) const = default;
};

/// Outcome of one evaluation.
struct EpisodeResult {
    double reward = 0.0;         ///< balls / Task::reward_divisor()
    int balls = 0;               ///< balls scored over all starts
    long steps_run = 0;          ///< steps run over all starts
    bool stopped_early = false;  ///< the stand-still rule ended the evaluation
    int nan_outputs = 0;         ///< controller outputs that were NaN (replaced by 0)
    Milestones milestones;       ///< steps of the task reached, all starts
};

/// What an observer of run_episode sees after each step.
struct StepView {
    int start = 0;
    int step = 0;
    Pose pose;                       ///< pose at which the inputs were sensed (before the move)
    const float* inputs = nullptr;   ///< the 12 inputs given to the controller
    const float* outputs = nullptr;  ///< the 3 outputs after NaN replacement and clamping
    bool carrying = false;           ///< after this step's action
    int balls = 0;                   ///< balls scored so far, all starts
    bool door_open = false;          ///< after this step's action (a switch press opens it)
    std::uint32_t lit = 0;           ///< lights lit after this step's action (bit i: Task::lights()[i])
};

/// An observer that ignores every step.
struct IgnoreSteps {
    void operator()(const StepView&) const {}
};

/// The mutable state of one evaluation of a task, advanced one step at a time.
/// run_episode() drives it; use it directly only to script unusual loops
/// (tests). Holds no heap memory of its own and allocates nothing per step.
/// The task must outlive the episode.
class Episode {
public:
    /// Throws DataError when a non-empty buffer of `recording` has the wrong size.
    Episode(const Task& task, const Recording& recording = {});

    /// Begins start `index` (0 <= index < starts): pose, sensors, flags and
    /// lights reset as in the original's instance() (docs/original.md: objects).
    void begin_start(int index);
    /// The 12 inputs of the current step (sensed at the end of the previous move).
    void read_inputs(float* inputs) const {
        fill_inputs(readings_, bumper_left_, bumper_right_, carrying_, inputs);
    }
    /// Runs the rest of the step: replaces NaN outputs by 0 (counted) and
    /// clamps them to [0, 1] in place, records, applies the action at the
    /// current pose, ticks the switch timer, moves, applies the stand-still
    /// rule and senses at the new pose. `inputs`, when given, are
    /// read_inputs()' of this step: the recording copies them.
    void act(float* outputs, const float* inputs = nullptr);
    /// act() in two halves, for lanes of episodes: the NaN replacement and
    /// the clamping, then the rest on the clamped outputs.
    void clamp_outputs(float* outputs) {
        // outputs at the sim boundary: NaN counted and replaced by 0, then clamped
        for (int i = 0; i < kOutputs; ++i) {
            if (std::isnan(outputs[i])) {
                outputs[i] = 0.0f;
                ++nan_outputs_;
            }
            outputs[i] = std::clamp(outputs[i], 0.0f, 1.0f);
        }
    }
    void act_clamped(const float* outputs, const float* inputs = nullptr);
    /// act_clamped() in three parts, for lanes that move and sense several episodes at once
    /// (portable runs, run_episode_queue): the recording, the action and the switch timer at
    /// the current pose; then the move to `next` (move_pose()'s answer, from move_lanes(),
    /// with `heading` the cos and sin of next.heading) and the contact test (`touches`:
    /// whether the disc at `next` overlaps a wall, and `near` its walls near the disc, from
    /// Arena::disc_overlaps_lanes(); contact() is none otherwise), the stand-still rule and the
    /// light sensors at the pose reached; then the three laser distances at that pose (from
    /// sense_lasers_lanes()) and the step's count.
    void act_before_move(const float* outputs, const float* inputs = nullptr);
    void move_to(const Pose& next, const CosSin& heading, bool touches, std::uint32_t near);
    void end_move(const std::array<double, 3>& lasers) {
        readings_.laser = lasers;
        ++step_;
        ++steps_run_;
    }
    /// Ends the episode: pads the recording after an early stop, returns the result.
    EpisodeResult finish();

    const Pose& pose() const { return pose_; }
    bool carrying() const { return carrying_; }
    bool collided() const { return collided_; }
    bool door_open() const { return state_.door_open; }
    std::uint32_t lit() const { return state_.lit; }
    int balls() const { return balls_; }
    /// Milestones reached so far, all starts.
    const Milestones& milestones() const { return milestones_; }
    int still_steps() const { return still_steps_; }
    bool stopped() const { return stopped_; }
    int start() const { return start_; }
    int step() const { return step_; }
    /// Steps left before the switch re-arms (target task); 0 when armed.
    int switch_timer() const { return switch_timer_; }
    /// Raw readings at the current pose.
    const SensorReadings& readings() const { return readings_; }

    /// Places the robot (test scenes); senses at the new pose.
    void set_pose(const Pose& pose);
    /// Sets the carried flag (test scenes).
    void set_carrying(bool carrying) { carrying_ = carrying; }

private:
    void record(const float* inputs, const float* outputs);  // inputs: null, or read_inputs()'s
    void apply_action(float action);
    void move(float left_output, float right_output);
    void take_move(const Pose& next, const Contact& contact);
    // the stand-still rule against the pose before the move
    void still_rule(const Pose& before);
    // the stand-still rule, the sensing and the counters
    void end_step(const Pose& before);

    const Task* task_;
    Recording recording_;
    CosSinMemos memos_;  // this evaluation's repeats of cos and sin
    Pose pose_;
    WorldState state_;
    SensorReadings readings_;
    bool bumper_left_ = false;
    bool bumper_right_ = false;
    bool carrying_ = false;
    bool collided_ = false;
    bool stopped_ = false;
    int switch_timer_ = 0;
    int balls_ = 0;
    Milestones milestones_;
    int still_steps_ = 0;
    int nan_outputs_ = 0;
    int start_ = -1;
    int step_ = 0;
    long steps_run_ = 0;
    std::size_t rows_written_ = 0;
    std::size_t cells_written_ = 0;
};

/// Runs one evaluation of `controller` on `task` (the loop order of docs/original.md: arena)
/// and records into `recording`. Controller concept:
///   void reset();                                   // at each start, state to 0
///   void step(const float* inputs, float* outputs); // 12 inputs -> 3 outputs
/// and optionally `void observe_pose(const Pose&)`, called before each step
/// with the true pose (the scripted controller). `observer(const StepView&)`
/// is called after each step. Deterministic: the same controller gives
/// bit-identical results on any thread. Throws DataError on a mis-sized buffer.
template <class Controller, class Observer = IgnoreSteps>
EpisodeResult run_episode(const Task& task, Controller& controller, const Recording& recording = {},
                          Observer&& observer = {}) {
    Episode episode(task, recording);
    std::array<float, kInputs> inputs{};
    std::array<float, kOutputs> outputs{};
    const TaskConfig& config = task.config();
    for (int start = 0; start < config.starts && !episode.stopped(); ++start) {
        episode.begin_start(start);
        controller.reset();
        for (int step = 0; step < config.steps_per_start; ++step) {
            episode.read_inputs(inputs.data());
            const Pose pose = episode.pose();
            if constexpr (requires { controller.observe_pose(pose); }) controller.observe_pose(pose);
            controller.step(inputs.data(), outputs.data());
            episode.act(outputs.data(), inputs.data());
            observer(StepView{start, step, pose, inputs.data(), outputs.data(), episode.carrying(),
                              episode.balls(), episode.door_open(), episode.lit()});
            if (episode.stopped()) break;
        }
    }
    return episode.finish();
}

/// Runs evaluations 0 to jobs - 1 in the lanes of `controller`: every lane
/// runs one evaluation at a time, step by step with the other lanes (only the
/// controller's step is shared), and takes the next job as soon as its
/// evaluation ends, by the stand-still rule or after its last start. Each
/// job's result and records are those run_episode gives its policy alone.
/// `recording_of(job)` gives a job's Recording; `done(job, result)` receives
/// its EpisodeResult once its records are complete. Controller concept:
///   std::size_t lanes() const;                         // lanes to fill, 1 to 32
///   void load(std::size_t lane, std::size_t job);      // the job's policy, states 0
///   void reset(std::size_t lane);                      // states 0, at each start
///   void set_inputs(std::size_t lane, const float*);   // 12 inputs of a lane
///   void step();                                       // every lane
///   void get_outputs(std::size_t lane, float*) const;  // 3 outputs of a lane
/// Throws DataError on a mis-sized buffer.
template <class Controller, class RecordingOf, class Done>
void run_episode_queue(const Task& task, Controller& controller, std::size_t jobs, RecordingOf&& recording_of,
                       Done&& done) {
    const std::size_t lanes = std::min(controller.lanes(), jobs);
    STEPSTONE_ASSERT(lanes <= 32);
    const TaskConfig& config = task.config();
    struct Lane {
        std::size_t job = 0;
        int start = 0;
        int step = 0;  // within the start
    };
    std::vector<Lane> lane_state(lanes);
    std::vector<std::optional<Episode>> episodes(lanes);
    std::size_t next_job = 0;
    std::uint32_t running = 0;  // bit l: lane l runs an evaluation
    const auto take_next_job = [&](std::size_t l) {
        const std::size_t job = next_job++;
        controller.load(l, job);
        episodes[l].emplace(task, recording_of(job));
        lane_state[l] = Lane{job, 0, 0};
        episodes[l]->begin_start(0);
        running |= 1u << l;
    };
    for (std::size_t l = 0; l < lanes; ++l) take_next_job(l);

    // portable runs move and sense every lane at once (move_lanes: the odometry with
    // portable::sincos_lanes, the scalar function's bits; Arena::disc_overlaps_lanes: the contact
    // test's common case; sense_lasers_lanes: the lasers); libm runs step each lane alone
    const bool portable = config.math == Math::portable;
    std::array<std::array<float, kInputs>, 32> inputs{};
    std::array<std::array<float, kOutputs>, 32> outputs{};
    std::array<std::uint8_t, 32> lane_of{};  // lane of each moved slot
    MoveLanes moves;
    alignas(64) std::array<double, 32> reached_x{};
    alignas(64) std::array<double, 32> reached_y{};
    alignas(64) std::array<std::array<double, 32>, 3> lasers{};
    std::array<std::uint32_t, 32> near{};  // each moved slot's walls near its disc
    while (running != 0) {
        for (std::uint32_t bits = running; bits != 0; bits &= bits - 1) {
            const auto l = static_cast<std::size_t>(std::countr_zero(bits));
            episodes[l]->read_inputs(inputs[l].data());
            controller.set_inputs(l, inputs[l].data());
        }
        controller.step();
        std::size_t count = 0;
        std::uint32_t door_open = 0;
        for (std::uint32_t bits = running; bits != 0; bits &= bits - 1) {
            const auto l = static_cast<std::size_t>(std::countr_zero(bits));
            controller.get_outputs(l, outputs[l].data());
            Episode& episode = *episodes[l];
            episode.clamp_outputs(outputs[l].data());
            if (!portable) continue;
            episode.act_before_move(outputs[l].data(), inputs[l].data());
            const Pose& pose = episode.pose();
            moves.x[count] = pose.x;
            moves.y[count] = pose.y;
            moves.heading[count] = pose.heading;
            moves.left[count] = outputs[l][0];
            moves.right[count] = outputs[l][1];
            door_open |= static_cast<std::uint32_t>(episode.door_open()) << count;
            lane_of[count++] = static_cast<std::uint8_t>(l);
        }
        if (portable) {
            moves.count = count;
            move_lanes(moves);
            const std::uint32_t touches = task.arena().disc_overlaps_lanes(
                moves.next_x.data(), moves.next_y.data(), door_open, count, near.data());
            for (std::size_t slot = 0; slot < count; ++slot) {
                Episode& episode = *episodes[lane_of[slot]];
                episode.move_to(Pose{moves.next_x[slot], moves.next_y[slot], moves.next_heading[slot]},
                                CosSin{moves.next_cos[slot], moves.next_sin[slot]},
                                ((touches >> slot) & 1u) != 0, near[slot]);
                reached_x[slot] = episode.pose().x;  // a blocked move keeps the position
                reached_y[slot] = episode.pose().y;
            }
            sense_lasers_lanes(task.arena(), reached_x.data(), reached_y.data(), moves.next_cos.data(),
                               moves.next_sin.data(), door_open, count,
                               {lasers[0].data(), lasers[1].data(), lasers[2].data()});
        }
        std::size_t slot = 0;
        for (std::uint32_t bits = running; bits != 0; bits &= bits - 1) {
            const auto l = static_cast<std::size_t>(std::countr_zero(bits));
            Episode& episode = *episodes[l];
            Lane& lane = lane_state[l];
            if (portable) {
                STEPSTONE_ASSERT(lane_of[slot] == l);
                episode.end_move({lasers[0][slot], lasers[1][slot], lasers[2][slot]});
                ++slot;
            } else {
                episode.act_clamped(outputs[l].data(), inputs[l].data());
            }
            // run_episode's loops: the next step, else the next start, else the end
            bool ended = episode.stopped();
            if (!ended && ++lane.step == config.steps_per_start) {
                lane.step = 0;
                if (++lane.start == config.starts) {
                    ended = true;
                } else {
                    episode.begin_start(lane.start);
                    controller.reset(l);
                }
            }
            if (!ended) continue;
            done(lane.job, episode.finish());
            running &= ~(1u << l);
            if (next_job < jobs) take_next_job(l);
        }
    }
}

}  // namespace stepstone::sim
