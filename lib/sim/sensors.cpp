#include "sim/sensors.hpp"

#include <bit>
#include <algorithm>
#include <cmath>

#include "core/assert.hpp"
#include "core/error.hpp"
#include "core/text.hpp"
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

namespace {

// lasers, then lights culled by colour already seen and by the windows before
// any line of sight; `blocked(index, light)` answers the sight-line question
template <class Blocked>
void sense_with(const Arena& arena, std::span<const Light> lights, const Pose& pose, const WorldState& state,
                SensorReadings& out, Blocked&& blocked) {
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
        if (blocked(index, light)) continue;
        out.light[first] = out.light[first] || plus;
        out.light[first + 1] = out.light[first + 1] || minus;
    }
}

// the hull of a light and a cell can meet a wall only if no axis separates
// them; the axes tried are the cell's and the normals of the light-to-corner
// lines, a superset of the hull's edge normals
bool hull_meets(const Light& light, double cx0, double cy0, double cx1, double cy1, const WallBox& wall) {
    const double px[5] = {light.x, cx0, cx1, cx0, cx1};
    const double py[5] = {light.y, cy0, cy0, cy1, cy1};
    const double wx[4] = {wall.x0, wall.x1, wall.x0, wall.x1};
    const double wy[4] = {wall.y0, wall.y0, wall.y1, wall.y1};
    auto separated = [&](double ax, double ay) {
        double plo = 1e300, phi = -1e300, wlo = 1e300, whi = -1e300;
        for (int i = 0; i < 5; ++i) {
            const double p = px[i] * ax + py[i] * ay;
            plo = std::min(plo, p);
            phi = std::max(phi, p);
        }
        for (int i = 0; i < 4; ++i) {
            const double p = wx[i] * ax + wy[i] * ay;
            wlo = std::min(wlo, p);
            whi = std::max(whi, p);
        }
        // a small margin keeps the table conservative against rounding
        return phi < wlo - 1e-6 || whi < plo - 1e-6;
    };
    if (separated(1.0, 0.0) || separated(0.0, 1.0)) return false;
    for (int i = 1; i < 5; ++i) {
        const double ex = px[i] - light.x;
        const double ey = py[i] - light.y;
        if ((ex != 0.0 || ey != 0.0) && separated(-ey, ex)) return false;
    }
    return true;
}

}  // namespace

SightTable::SightTable(const Arena& arena, std::span<const Light> lights) : lights_(lights.begin(), lights.end()) {
    if (lights.size() > static_cast<std::size_t>(kMaxLights)) {
        throw DataError(concat("a task may have at most ", kMaxLights, " lights, got ", lights.size()));
    }
    const auto walls = arena.walls();
    masks_.assign(lights_.size() * kColumns * kRows, 0);
    for (std::size_t l = 0; l < lights_.size(); ++l) {
        for (int row = 0; row < kRows; ++row) {
            for (int column = 0; column < kColumns; ++column) {
                std::uint16_t mask = 0;
                for (std::size_t w = 0; w < walls.size(); ++w) {
                    if (hull_meets(lights_[l], column * kCell, row * kCell, (column + 1) * kCell, (row + 1) * kCell,
                                   walls[w])) {
                        mask = static_cast<std::uint16_t>(mask | (1u << w));
                    }
                }
                masks_[(l * kRows + static_cast<std::size_t>(row)) * kColumns + static_cast<std::size_t>(column)] = mask;
            }
        }
    }
}

std::uint32_t SightTable::candidates(std::size_t index, double x, double y) const {
    const double column = std::floor(x / kCell);
    const double row = std::floor(y / kCell);
    if (!(column >= 0.0 && column < kColumns && row >= 0.0 && row < kRows)) return ~0u;
    return masks_[(index * kRows + static_cast<std::size_t>(row)) * kColumns + static_cast<std::size_t>(column)];
}

void sense(const Arena& arena, const SightTable& sight, const Pose& pose, const WorldState& state,
           SensorReadings& out) {
    sense_with(arena, sight.lights(), pose, state, out, [&](std::size_t index, const Light& light) {
        const std::uint32_t walls = sight.candidates(index, pose.x, pose.y);
        return walls != 0 && arena.segment_blocked_by(walls, light.x, light.y, pose.x, pose.y, state.door_open);
    });
}

void sense(const Arena& arena, std::span<const Light> lights, const Pose& pose, const WorldState& state,
           SensorReadings& out) {
    sense_with(arena, lights, pose, state, out, [&](std::size_t, const Light& light) {
        return arena.segment_blocked(light.x, light.y, pose.x, pose.y, state.door_open);
    });
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
