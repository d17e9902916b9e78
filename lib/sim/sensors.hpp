#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "sim/arena.hpp"
#include "sim/robot.hpp"
#include "sim/units.hpp"

namespace stepstone::sim {

/// Number of controller inputs, outputs, and behaviour channels (inputs then outputs).
inline constexpr int kInputs = 12;
inline constexpr int kOutputs = 3;
inline constexpr int kChannels = kInputs + kOutputs;

/// Colour of an illuminated object; each colour has two light sensors.
enum class LightKind : std::uint8_t { ball = 0, basket = 1, switch_light = 2 };

/// An illuminated object (fastsim's IlluminatedSwitch): a point light in units.
/// Its radius plays no part in sensing.
struct Light {
    LightKind kind = LightKind::ball;
    double x = 0.0;
    double y = 0.0;
};

/// Most lights a task may have (bits of WorldState::lit).
inline constexpr int kMaxLights = 16;

/// The part of the world that changes during an episode and that sensors see.
struct WorldState {
    bool door_open = false;
    std::uint32_t lit = 0;  ///< bit i set = light i is on
};

/// Raw readings of the exteroceptive sensors (inputs 0-8).
struct SensorReadings {
    /// Distance to the wall along each laser (+pi/4, -pi/4, 0), units; -1 when none within range.
    std::array<double, 3> laser{};
    /// Light sensors in input order: ball +-pi/4, basket +-pi/4, switch +-pi/4.
    std::array<bool, 6> light{};
};

/// Bearing (radians) of each laser relative to the heading, in input order.
inline constexpr std::array<double, 3> kLaserAngles{kPi / 4, -kPi / 4, 0.0};
/// Bearing (radians) of the two sensors of each colour, + first.
inline constexpr std::array<double, 2> kLightSensorAngles{kPi / 4, -kPi / 4};

/// Line-of-sight candidates, precomputed: for each light and each 10 x 10
/// cell of robot positions, the walls that can cross a segment from the light
/// to a point of the cell (separating-axis test of the light-cell hull against
/// each wall). Most entries are empty, so most sight lines cost nothing; the
/// others test only their few candidates exactly. Immutable once built.
///
/// Laid out for sense(): the lights' coordinates as arrays, and per cell the
/// candidate masks of every light side by side with the set of lights that
/// no wall can hide from that cell and the set that a wall hides from all of
/// it (every light-corner segment crosses the wall shrunk by kHiddenMargin;
/// the points whose segments cross a convex box form a convex set, so the
/// whole cell's do, with a margin far above rounding).
class SightTable {
public:
    /// Side of a cell, in units.
    static constexpr double kCell = 10.0;
    static constexpr int kColumns = 60;  ///< 600 units
    static constexpr int kRows = 40;     ///< 400 units
    /// Depth, in units, by which a hiding wall's box is shrunk for the test.
    static constexpr double kHiddenMargin = 0.01;

    /// One cell's view of the lights.
    struct Cell {
        const std::uint16_t* walls;  ///< [light]: candidate walls of its sight line
        std::uint32_t clear;         ///< bit i set = no wall can block light i
        std::uint32_t hidden;        ///< bit i set = a wall blocks light i from every point of the cell
    };

    /// Throws DataError when there are more than kMaxLights lights.
    SightTable(const Arena& arena, std::span<const Light> lights);

    std::span<const Light> lights() const { return lights_; }
    /// Walls (bit i = arena.walls()[i]) that may block the sight line from
    /// light `index` to (x, y); every wall when (x, y) is off the grid.
    std::uint32_t candidates(std::size_t index, double x, double y) const;
    /// Every light's candidates at (x, y) with the door open or closed; off
    /// the grid, every wall and no clear or hidden light.
    Cell cell(double x, double y, bool door_open) const;

    /// Lights that may lie closer than kReach to (x, y): a superset, from the cell of (x, y)
    /// (each light whose reach disc meets the cell grown by a unit, so the cell found by a
    /// product instead of a quotient is as good); every light off the grid.
    std::uint32_t reach_candidates(double x, double y) const {
        const double column = x * (1.0 / kCell);
        const double row = y * (1.0 / kCell);
        if (!(column >= 0.0 && column < kColumns && row >= 0.0 && row < kRows)) return ~0u;
        return reach_[static_cast<std::size_t>(static_cast<int>(row)) * kColumns +
                      static_cast<std::size_t>(static_cast<int>(column))];
    }

    /// Light coordinates, padded to kMaxLights.
    const std::array<double, kMaxLights>& xs() const { return xs_; }
    const std::array<double, kMaxLights>& ys() const { return ys_; }
    /// Lights of each LightKind (bit i = lights()[i]).
    const std::array<std::uint32_t, 3>& kinds() const { return kinds_; }

private:
    std::size_t cell_index(double x, double y) const;

    std::vector<Light> lights_;
    // (on cache lines: the window kernels load four or two lights' coordinates at a time)
    alignas(64) std::array<double, kMaxLights> xs_{};
    alignas(64) std::array<double, kMaxLights> ys_{};
    std::array<std::uint32_t, 3> kinds_{};
    std::vector<std::uint16_t> masks_;  // [row][column][light], stride kMaxLights; one more cell: off the grid
    struct Summary {
        std::uint32_t clear = 0;
        std::uint32_t hidden_by_fixed = 0;  // by a wall other than the door
        std::uint32_t hidden_by_door = 0;   // by the closed door
    };
    std::vector<Summary> summaries_;  // [row][column], then off the grid
    std::vector<std::uint32_t> reach_;  // [row][column]: reach_candidates()
};

/// Readings at `pose` with the fast geometry and precomputed sight lines;
/// same results as the overload below. The hot path.
void sense(const Arena& arena, const SightTable& sight, const Pose& pose, const WorldState& state,
           SensorReadings& out);

/// The light sensors of sense() alone (`out.laser` is left as it is), for lanes whose lasers
/// sense_lasers_lanes() read together.
void sense_lights(const Arena& arena, const SightTable& sight, const Pose& pose, const WorldState& state,
                  SensorReadings& out);

/// The lasers of sense() for `count` (at most 32) poses at once: lane l at (x[l], y[l]) with
/// its heading's cos c[l] and sin s[l], the door open where bit l of `door_open` is set;
/// out[i][l] gets laser i's distance, the bits sense() gives (Arena::ray_distances_lanes).
void sense_lasers_lanes(const Arena& arena, const double* x, const double* y, const double* c,
                        const double* s, std::uint32_t door_open, std::size_t count, double* const (&out)[3]);

/// Readings at `pose` with the fast geometry. Lasers are exact ray/box
/// distances; a light sensor fires when a lit light of its colour lies strictly
/// inside its window (bearing in (angle - kLightWindow/2, angle + kLightWindow/2))
/// and no wall crosses the segment between the light and the robot centre.
/// Allocation-free; `lights` holds at most kMaxLights entries.
void sense(const Arena& arena, std::span<const Light> lights, const Pose& pose, const WorldState& state,
           SensorReadings& out);

/// Laser input value from a distance: 1 - d / 320, 0 when d is -1 (nothing within range).
inline float laser_input(double distance) {
    return distance < 0.0 ? 0.0f : static_cast<float>(1.0 - distance / kLaserRange);
}

/// Fills the 12 controller inputs in the order of docs/original.md (arena).
inline void fill_inputs(const SensorReadings& readings, bool bumper_left, bool bumper_right, bool carrying,
                        float* inputs) {
    for (std::size_t i = 0; i < 3; ++i) inputs[i] = laser_input(readings.laser[i]);
    for (std::size_t i = 0; i < 6; ++i) inputs[3 + i] = readings.light[i] ? 1.0f : 0.0f;
    inputs[9] = bumper_left ? 1.0f : 0.0f;
    inputs[10] = bumper_right ? 1.0f : 0.0f;
    inputs[11] = carrying ? 1.0f : 0.0f;
}

/// Column names of the behaviour matrix: 12 inputs then 3 outputs.
std::span<const char* const> channel_names();

}  // namespace stepstone::sim
