#pragma once

// The robot trajectory shared by both sides of `stepstone bench sim`.

#include <array>
#include <cstdint>
#include <vector>

namespace stepstone::bench {

/// A fixed pseudo-random drive: every `segment` steps the robot is placed at
/// the next start pose, then follows the wheel commands. The start poses are
/// spread over the reachable arena (discs of radius 25 clear of every wall of
/// the door-closed arena), so the sensors see every room, as an evolving
/// population does; open-loop commands alone would leave the robot pressed
/// against one wall most of the time.
struct DrivePlan {
    int segment = 50;                            ///< steps between two placements
    std::vector<std::array<float, 3>> starts;    ///< x, y, heading of each segment
    std::vector<std::array<float, 2>> commands;  ///< left and right outputs in [0, 1], one per step
};

/// A plan of `steps` steps (a multiple of the segment length is best):
/// commands are runs of 10 to 59 steps, full speed ahead (3 in 5) or a
/// random pair of outputs. Deterministic in `seed`.
DrivePlan drive_plan(int steps, std::uint64_t seed);

}  // namespace stepstone::bench
