#include "bench/drive_plan.hpp"

#include <algorithm>
#include <numbers>

#include "core/rng.hpp"
#include "reference/fastsim_baseline.hpp"

namespace stepstone::bench {

using namespace stepstone::reference;  // the baselines

namespace {

// true when a disc of `radius` around (x, y) touches no wall rectangle
bool clear_of_walls(float x, float y, float radius, const std::vector<WallRect>& walls) {
    for (const auto& w : walls) {
        const float cx = std::clamp(x, w.x0, w.x1);
        const float cy = std::clamp(y, w.y0, w.y1);
        if ((cx - x) * (cx - x) + (cy - y) * (cy - y) < radius * radius) return false;
    }
    return true;
}

}  // namespace

DrivePlan drive_plan(int steps, std::uint64_t seed) {
    Rng rng(seed);
    DrivePlan plan;
    const auto walls = arena_walls(Door::closed);
    const int segments = (steps + plan.segment - 1) / plan.segment;
    while (static_cast<int>(plan.starts.size()) < segments) {
        const auto x = static_cast<float>(rng.uniform(0, 600));
        const auto y = static_cast<float>(rng.uniform(0, 400));
        const auto heading = static_cast<float>(rng.uniform(-std::numbers::pi, std::numbers::pi));
        if (clear_of_walls(x, y, 25.0f, walls)) plan.starts.push_back({x, y, heading});
    }
    while (static_cast<int>(plan.commands.size()) < steps) {
        std::array<float, 2> command{1.0f, 1.0f};
        if (rng.below(5) >= 3)
            command = {static_cast<float>(rng.uniform()), static_cast<float>(rng.uniform())};
        const auto length = 10 + rng.below(50);
        for (std::uint64_t k = 0; k < length && static_cast<int>(plan.commands.size()) < steps; ++k) {
            plan.commands.push_back(command);
        }
    }
    return plan;
}

}  // namespace stepstone::bench
