#pragma once

// What the episode and milestone tests share: the bottom wall's face and one
// step with the outputs given by hand.

#include <array>

#include "sim/episode.hpp"

namespace stepstone::simtest {

/// The bottom wall's face from the bitmap: pixel i covers [(i - 0.5) 600/296, (i + 0.5) 600/296).
inline constexpr double kBottomFace = 194.5 * 600.0 / 296.0;  // 394.2568

/// One step with the wheel outputs `left`, `right` and the action output `action`; returns them.
inline std::array<float, sim::kOutputs> act(sim::Episode& episode, float left, float right, float action) {
    std::array<float, sim::kOutputs> outputs{left, right, action};
    episode.act(outputs.data());
    return outputs;
}

}  // namespace stepstone::simtest
