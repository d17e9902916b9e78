#include "sim/sensors.hpp"

#include <bit>
#include <cmath>

#include "core/assert.hpp"
#include "sim/units.hpp"

namespace stepstone::sim {

namespace {

// the edges of a window as unit vectors in the robot frame (x forward, y
// towards positive bearings): a bearing lies strictly inside the window when
// it is strictly counter-clockwise of the first and clockwise of the second
struct Window {
    double lo_x, lo_y, hi_x, hi_y;
};

Window window_of(double angle) {
    const double lo = angle - kLightWindow / 2;
    const double hi = angle + kLightWindow / 2;
    return {std::cos(lo), std::sin(lo), std::cos(hi), std::sin(hi)};
}

const Window kWindows[2] = {window_of(kLightSensorAngles[0]), window_of(kLightSensorAngles[1])};

bool inside(const Window& w, double u, double v) {
    return w.lo_x * v - w.lo_y * u > 0.0 && u * w.hi_y - v * w.hi_x > 0.0;
}

constexpr const char* kChannelNames[kChannels] = {
    "laser_p45",  "laser_m45",   "laser_0",     "ball_p45",    "ball_m45",   "basket_p45",
    "basket_m45", "switch_p45",  "switch_m45",  "bumper_left", "bumper_right", "carrying",
    "left_wheel", "right_wheel", "action",
};

}  // namespace

void sense(const Arena& arena, std::span<const Light> lights, const Pose& pose, const WorldState& state,
           SensorReadings& out) {
    STEPSTONE_ASSERT(lights.size() <= static_cast<std::size_t>(kMaxLights));
    const double c = std::cos(pose.heading);
    const double s = std::sin(pose.heading);

    // lasers at +pi/4, -pi/4 and 0: rotate the heading by the fixed angles
    constexpr double kHalfRoot2 = 0.70710678118654752440;
    const double dirs[3][2] = {{(c - s) * kHalfRoot2, (s + c) * kHalfRoot2},
                               {(c + s) * kHalfRoot2, (s - c) * kHalfRoot2},
                               {c, s}};
    for (std::size_t i = 0; i < 3; ++i) {
        out.laser[i] = arena.ray_distance(pose.x, pose.y, dirs[i][0], dirs[i][1], kLaserRange, state.door_open);
    }

    // lights: cull by colour already seen and by the windows before any line of sight
    out.light = {};
    for (std::uint32_t lit = state.lit; lit != 0; lit &= lit - 1) {
        const auto index = static_cast<std::size_t>(std::countr_zero(lit));
        if (index >= lights.size()) break;
        const Light& light = lights[index];
        const std::size_t first = 2 * static_cast<std::size_t>(light.kind);
        if (out.light[first] && out.light[first + 1]) continue;
        const double dx = light.x - pose.x;
        const double dy = light.y - pose.y;
        const double u = dx * c + dy * s;
        const double v = dy * c - dx * s;
        const bool plus = !out.light[first] && inside(kWindows[0], u, v);
        const bool minus = !out.light[first + 1] && inside(kWindows[1], u, v);
        if (!plus && !minus) continue;
        if (arena.segment_blocked(light.x, light.y, pose.x, pose.y, state.door_open)) continue;
        out.light[first] = out.light[first] || plus;
        out.light[first + 1] = out.light[first + 1] || minus;
    }
}

void fill_inputs(const SensorReadings& readings, bool bumper_left, bool bumper_right, bool carrying,
                 float* inputs) {
    for (std::size_t i = 0; i < 3; ++i) inputs[i] = laser_input(readings.laser[i]);
    for (std::size_t i = 0; i < 6; ++i) inputs[3 + i] = readings.light[i] ? 1.0f : 0.0f;
    inputs[9] = bumper_left ? 1.0f : 0.0f;
    inputs[10] = bumper_right ? 1.0f : 0.0f;
    inputs[11] = carrying ? 1.0f : 0.0f;
}

std::span<const char* const> channel_names() { return kChannelNames; }

}  // namespace stepstone::sim
