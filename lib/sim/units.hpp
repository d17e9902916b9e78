#pragma once

// Units of the simulator. The arena keeps the original experiment's world
// units: the map is 600 units wide, the usable arena about 600 x 400, the
// origin is the top-left corner and y points down, so a positive angle turns
// clockwise on screen. Angles are in radians, time is counted in steps (one
// control tick). Names carry a unit suffix only where it differs.

namespace stepstone::sim {

inline constexpr double kPi = 3.14159265358979323846;

/// Robot radius, in units (fastsim's Robot(20)).
inline constexpr double kRobotRadius = 20.0;
/// Distance between the two wheels, in units (2 x radius).
inline constexpr double kWheelBase = 40.0;
/// Largest wheel displacement in one step, in units (output 1 gives +4, 0 gives -4).
inline constexpr double kMaxWheelStep = 4.0;
/// Laser range, in units (8 x radius x 2).
inline constexpr double kLaserRange = 320.0;
/// Full angular window of a light sensor, in radians.
inline constexpr double kLightWindow = kPi / 2 + 0.01;
/// Distance below which the action output picks a ball or presses the switch, in units.
inline constexpr double kReach = 20.0;
/// A pose change below this (in units and in radians) counts as a still step.
inline constexpr double kStillEpsilon = 1e-4;
/// Width of the map in units, and tiles per side of the diversity grid.
inline constexpr double kMapSize = 600.0;
inline constexpr int kGridTiles = 12;

}  // namespace stepstone::sim
