#pragma once

#include <array>
#include <memory>

#include "sim/task.hpp"

namespace stepstone::sim::tasks {

/// Ball positions of the original (docs/original.md: objects), units.
inline constexpr std::array<Light, 8> kBalls{{
    {LightKind::ball, 296.25, 50.625},
    {LightKind::ball, 296.25, 151.875},
    {LightKind::ball, 397.5, 50.625},
    {LightKind::ball, 397.5, 151.875},
    {LightKind::ball, 97.5, 50.625},  // behind the door, top-left: the target task's spawn point
    {LightKind::ball, 97.5, 151.875},
    {LightKind::ball, 97.5, 253.125},
    {LightKind::ball, 97.5, 354.375},
}};
/// The four basket lights above the basket, units.
inline constexpr std::array<Light, 4> kBasketLights{{
    {LightKind::basket, 262.5, 385.0},
    {LightKind::basket, 330.0, 385.0},
    {LightKind::basket, 285.0, 385.0},
    {LightKind::basket, 307.5, 385.0},
}};
/// The switch, units.
inline constexpr Light kSwitch{LightKind::switch_light, 532.5, 40.5};

/// Source task: 8 lit balls, the basket lights and the switch; the switch opens
/// the door until the next start.
std::shared_ptr<const Task> make_source_task(const TaskConfig& config);
/// Target task (VARIANT_SW2): door always open, one unlit ball at (97.5, 50.625)
/// that each switch press lights; the switch re-arms 100 steps after a press.
std::shared_ptr<const Task> make_target_task(const TaskConfig& config);

}  // namespace stepstone::sim::tasks
