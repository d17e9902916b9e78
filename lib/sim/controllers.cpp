#include "sim/controllers.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "sim/arena_spec.hpp"
#include "sim/units.hpp"

namespace stepstone::sim {

namespace {

// rooms of the arena in the order they connect: left room, lower band left of
// the stubs, lower band right of the stubs, upper room
enum Room { left_room = 0, lower_left = 1, lower_right = 2, upper = 3 };

struct Gate {
    double low_x, low_y;    // waypoint on the lower-numbered room's side
    double high_x, high_y;  // waypoint on the other side
};

// the door, the gap between the stubs, the gap in the horizontal wall
constexpr std::array<Gate, 3> kGates{{
    {165.0, 304.0, 245.0, 304.0},
    {365.0, 304.0, 435.0, 304.0},
    {500.0, 245.0, 500.0, 160.0},
}};

Room room_of(double x, double y) {
    if (x < 204.7) return left_room;
    if (y < 202.7) return upper;
    return x < 399.3 ? lower_left : lower_right;
}

// where the robot stops before driving straight down onto the bottom wall
constexpr double kBasketApproachY = 330.0;
// source task: left-room balls first (the door's reward), then the upper room
constexpr std::array<int, 8> kSourceBallOrder{6, 7, 5, 4, 1, 0, 3, 2};

float output_of(double wheel) { return static_cast<float>((std::clamp(wheel, -4.0, 4.0) / 4.0 + 1.0) / 2.0); }

double distance(const Pose& pose, double x, double y) { return std::hypot(x - pose.x, y - pose.y); }

}  // namespace

void RandomController::step(const float*, float* outputs) {
    for (int i = 0; i < 3; ++i) outputs[i] = static_cast<float>(rng_.uniform());
}

ScriptedController::ScriptedController(TaskKind kind) : kind_(kind) { reset(); }

void ScriptedController::reset() {
    goal_ = Goal::press_switch;
    next_ball_ = 0;
    route_.clear();
    route_pos_ = 0;
    backing_ = 0;
    descending_ = false;
    pushing_ = false;
}

void ScriptedController::plan(Point target) {
    route_.clear();
    route_pos_ = 0;
    int from = room_of(pose_.x, pose_.y);
    const int to = room_of(target.x, target.y);
    // walk the chain of rooms through each gate's pair of waypoints
    while (from < to) {
        const Gate& g = kGates[static_cast<std::size_t>(from)];
        route_.push_back({g.low_x, g.low_y});
        route_.push_back({g.high_x, g.high_y});
        ++from;
    }
    while (from > to) {
        const Gate& g = kGates[static_cast<std::size_t>(from - 1)];
        route_.push_back({g.high_x, g.high_y});
        route_.push_back({g.low_x, g.low_y});
        --from;
    }
    route_.push_back(target);
}

void ScriptedController::drive_to(Point target, double speed, float* outputs) const {
    const double bearing = normalize_angle(std::atan2(target.y - pose_.y, target.x - pose_.x) - pose_.heading);
    double left = 0.0;
    double right = 0.0;
    if (std::fabs(bearing) > 0.6) {
        // turn on the spot: the heading changes by (right - left) / 40
        const double k = std::clamp(20.0 * bearing, -4.0, 4.0);
        left = -k;
        right = k;
    } else {
        const double k = std::clamp(10.0 * bearing, -2.0, 2.0);
        const double v = std::min(speed, 4.0 - std::fabs(k));
        left = v - k;
        right = v + k;
    }
    outputs[0] = output_of(left);
    outputs[1] = output_of(right);
}

// follows route_ to its end; true once within `tolerance` of the last point
bool ScriptedController::follow(double speed, double tolerance, float* outputs) {
    while (route_pos_ + 1 < route_.size() &&
           distance(pose_, route_[route_pos_].x, route_[route_pos_].y) < 12.0) {
        ++route_pos_;
    }
    const Point& point = route_[route_pos_];
    drive_to(point, speed, outputs);
    return route_pos_ + 1 == route_.size() && distance(pose_, point.x, point.y) < tolerance;
}

ScriptedController::Point ScriptedController::ball_target() const {
    const int ball = kind_ == TaskKind::target ? 4 : kSourceBallOrder[static_cast<std::size_t>(next_ball_)];
    const sim::Point& at = paper_arena().balls[static_cast<std::size_t>(ball)];
    return {at.x, at.y};
}

void ScriptedController::set_goal(Goal goal) {
    goal_ = goal;
    route_.clear();
    descending_ = false;
}

void ScriptedController::step(const float* inputs, float* outputs) {
    const bool carrying = inputs[11] > 0.5f;
    const bool bumped = inputs[9] > 0.5f || inputs[10] > 0.5f;
    // a forward drive that left the position unchanged was stopped by a wall
    const bool blocked = pushing_ && pose_.x == previous_.x && pose_.y == previous_.y;
    previous_ = pose_;
    pushing_ = false;
    outputs[2] = 0.0f;

    // after a release, back away from the wall before the next errand
    if (backing_ > 0) {
        outputs[0] = outputs[1] = 0.25f;
        if (--backing_ == 0) set_goal(kind_ == TaskKind::target ? Goal::press_switch : Goal::fetch_ball);
        return;
    }
    if (carrying && goal_ != Goal::score) set_goal(Goal::score);
    if (!carrying && goal_ == Goal::score) set_goal(Goal::fetch_ball);
    if (goal_ == Goal::fetch_ball && kind_ == TaskKind::source && next_ball_ >= 8) {
        // nothing left to fetch: turn on the spot (turning is not standing still)
        outputs[0] = 0.0f;
        outputs[1] = 1.0f;
        return;
    }

    switch (goal_) {
        case Goal::press_switch: {
            if (route_.empty()) plan({paper_arena().switch_light.x, paper_arena().switch_light.y});
            follow(3.0, 0.0, outputs);
            // the action applies at the current pose, so a press within reach succeeds now
            if (distance(pose_, paper_arena().switch_light.x, paper_arena().switch_light.y) < kReach - 2.0) {
                outputs[2] = 1.0f;
                set_goal(Goal::fetch_ball);
            }
            return;
        }
        case Goal::fetch_ball: {
            const Point ball = ball_target();
            if (route_.empty()) plan(ball);
            const bool arrived = follow(3.0, 3.0, outputs);
            if (distance(pose_, ball.x, ball.y) < kReach + 10.0) outputs[2] = 1.0f;
            // no ball where expected (already taken, or not spawned): next errand
            if (arrived) {
                if (kind_ == TaskKind::target) {
                    set_goal(Goal::press_switch);
                } else {
                    ++next_ball_;
                    set_goal(Goal::fetch_ball);
                }
            }
            return;
        }
        case Goal::score: {
            outputs[2] = 1.0f;  // keep holding the ball
            if (!descending_) {
                if (route_.empty()) plan({paper_arena().basket.centre.x, kBasketApproachY});
                descending_ = follow(3.0, 6.0, outputs);
                if (!descending_) return;
            }
            // drive straight down onto the bottom wall; release once pressed against it
            if (bumped || blocked) {
                outputs[2] = 0.0f;
                outputs[0] = outputs[1] = 0.25f;
                backing_ = 8;
                if (kind_ == TaskKind::source) ++next_ball_;
                return;
            }
            drive_to({paper_arena().basket.centre.x, 395.0}, pose_.y < 350.0 ? 3.0 : 1.0, outputs);
            pushing_ = outputs[0] > 0.5f && outputs[1] > 0.5f;
            return;
        }
    }
}

}  // namespace stepstone::sim
