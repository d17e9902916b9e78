#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "sim/sensors.hpp"
#include "sim/task.hpp"
#include "sim/units.hpp"

using namespace stepstone::sim;

namespace {

// one lit light of `kind` at `bearing` radians and `range` units from the pose
SensorReadings see_one(LightKind kind, const Pose& pose, double bearing, double range = 60.0) {
    const Arena arena;
    const std::vector<Light> lights{
        {kind, pose.x + range * std::cos(pose.heading + bearing), pose.y + range * std::sin(pose.heading + bearing)}};
    SensorReadings out;
    sense(arena, lights, pose, WorldState{false, 1u}, out);
    return out;
}

// the +pi/4 sensor covers bearings (pi/4 - w/2, pi/4 + w/2) with w = pi/2 + 0.01,
// i.e. (-0.005, 1.5758); the -pi/4 sensor covers (-1.5758, 0.005)
constexpr double kEdge = kPi / 4 + (kPi / 2 + 0.01) / 2;  // 1.5757963

}  // namespace

TEST_CASE("a light straight ahead fires both sensors of its colour", "[sim][sensors]") {
    const Pose pose{300.0, 101.25, 0.3};
    const auto out = see_one(LightKind::basket, pose, 0.0);
    CHECK(out.light == std::array<bool, 6>{false, false, true, true, false, false});
    // still both within the 0.01 rad overlap, only one just outside it
    CHECK(see_one(LightKind::basket, pose, 0.004).light[2]);
    CHECK(see_one(LightKind::basket, pose, 0.004).light[3]);
    CHECK(see_one(LightKind::basket, pose, 0.006).light[2]);
    CHECK_FALSE(see_one(LightKind::basket, pose, 0.006).light[3]);
    CHECK_FALSE(see_one(LightKind::basket, pose, -0.006).light[2]);
    CHECK(see_one(LightKind::basket, pose, -0.006).light[3]);
}

TEST_CASE("light sensor windows end at plus and minus 1.5758 rad", "[sim][sensors]") {
    const Pose pose{300.0, 101.25, -1.0};
    CHECK(see_one(LightKind::switch_light, pose, kEdge - 0.001).light[4]);
    CHECK_FALSE(see_one(LightKind::switch_light, pose, kEdge + 0.001).light[4]);
    CHECK(see_one(LightKind::switch_light, pose, -kEdge + 0.001).light[5]);
    CHECK_FALSE(see_one(LightKind::switch_light, pose, -kEdge - 0.001).light[5]);
    // behind the robot: nothing
    CHECK(see_one(LightKind::switch_light, pose, 3.0).light == std::array<bool, 6>{});
}

TEST_CASE("a light behind the divider is hidden, seen from the left room it fires", "[sim][sensors]") {
    const auto task = make_task(TaskConfig{});
    const std::uint32_t only_ball_4 = 1u << 4;  // ball 4 at (97.5, 50.625), in the left room
    SensorReadings out;
    // from the upper room facing west the ball's bearing is atan(50.625 / 202.5) = +0.245,
    // inside the +pi/4 window, but the divider (x 201.7-207.8) lies between
    sense(task->arena(), task->lights(), {300.0, 101.25, kPi}, {false, only_ball_4}, out);
    CHECK_FALSE(out.light[0]);
    CHECK_FALSE(out.light[1]);
    // from (100, 150) facing up (-pi/2) the bearing is atan2(-99.375, -2.5) + pi/2 = -0.025: the -pi/4 sensor
    sense(task->arena(), task->lights(), {100.0, 150.0, -kPi / 2}, {false, only_ball_4}, out);
    CHECK_FALSE(out.light[0]);
    CHECK(out.light[1]);
}

TEST_CASE("unlit objects are ignored by the light sensors", "[sim][sensors]") {
    const auto task = make_task(TaskConfig{});
    SensorReadings out;
    // the same view as above with ball 4 switched off, every other light on
    const std::uint32_t all_but_4 = task->initial_lit() & ~(1u << 4);
    sense(task->arena(), task->lights(), {100.0, 150.0, -kPi / 2}, {false, all_but_4}, out);
    // balls 5-7 are below the robot (behind it), so no ball sensor fires
    CHECK_FALSE(out.light[0]);
    CHECK_FALSE(out.light[1]);
}

TEST_CASE("laser inputs are 1 - d / 320 and 0 when nothing is in range", "[sim][sensors]") {
    CHECK(laser_input(-1.0) == 0.0f);
    CHECK(laser_input(0.0) == 1.0f);
    CHECK(laser_input(80.0) == Approx(0.75));
    CHECK(laser_input(320.0) == 0.0f);
}

TEST_CASE("inputs follow the original order", "[sim][sensors]") {
    SensorReadings readings;
    readings.laser = {0.0, 160.0, -1.0};
    readings.light = {true, false, false, true, true, false};
    float inputs[kInputs];
    fill_inputs(readings, true, false, true, inputs);
    const float want[kInputs] = {1.0f, 0.5f, 0.0f, 1.0f, 0.0f, 0.0f, 1.0f, 1.0f, 0.0f, 1.0f, 0.0f, 1.0f};
    for (int i = 0; i < kInputs; ++i) CHECK(inputs[i] == want[i]);
    CHECK(std::string(channel_names()[9]) == "bumper_left");
    CHECK(std::string(channel_names()[14]) == "action");
}
