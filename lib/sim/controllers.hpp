#pragma once

#include <cstdint>
#include <vector>

#include "core/rng.hpp"
#include "sim/robot.hpp"
#include "sim/task.hpp"

namespace stepstone::sim {

/// Outputs uniform in [0, 1) from its own seeded stream (not reset between starts).
class RandomController {
public:
    explicit RandomController(std::uint64_t seed) : rng_(seed) {}
    void reset() {}
    void step(const float* inputs, float* outputs);

private:
    Rng rng_;
};

/// Always the same outputs (tests, the stand-still rule).
class ConstantController {
public:
    ConstantController(float left, float right, float action) : outputs_{left, right, action} {}
    void reset() {}
    void step(const float*, float* outputs) const {
        for (int i = 0; i < 3; ++i) outputs[i] = outputs_[i];
    }

private:
    float outputs_[3];
};

/// A waypoint follower that reads the true pose (a test fixture users can run
/// too). Source task: press the switch, go through the door, fetch the
/// left-room balls and score them. Target task: press the switch, fetch the
/// spawned ball, score, and repeat. It drives between rooms through the gaps
/// and scores by pressing against the bottom wall under the basket lights.
class ScriptedController {
public:
    explicit ScriptedController(TaskKind kind);
    void reset();
    void observe_pose(const Pose& pose) { pose_ = pose; }
    void step(const float* inputs, float* outputs);

    /// What the controller is doing, for tests and the CSV reader.
    enum class Goal { press_switch, fetch_ball, score };
    Goal goal() const { return goal_; }

private:
    struct Point {
        double x, y;
    };
    void plan(Point target);
    void drive_to(Point target, double speed, float* outputs) const;
    bool follow(double speed, double tolerance, float* outputs);
    Point ball_target() const;
    void set_goal(Goal goal);

    TaskKind kind_;
    Pose pose_;
    Pose previous_;
    bool pushing_ = false;
    Goal goal_ = Goal::press_switch;
    bool descending_ = false;
    int next_ball_ = 0;
    std::vector<Point> route_;
    std::size_t route_pos_ = 0;
    int backing_ = 0;
};

}  // namespace stepstone::sim
