#pragma once

#include <memory>

#include "sim/task.hpp"

namespace stepstone::sim::tasks {

/// Source task: every ball of the arena lit, the basket lights and the switch;
/// the switch opens the door until the next start.
std::shared_ptr<const Task> make_source_task(const TaskConfig& config);
/// Target task (VARIANT_SW2): door always open, one unlit ball at the arena's
/// target_ball position (the paper's: (97.5, 50.625)) that each switch press
/// lights; the switch re-arms 100 steps after a press.
std::shared_ptr<const Task> make_target_task(const TaskConfig& config);

/// The lights of the arena's basket, then its switch, after `lights`.
void append_basket_and_switch(const ArenaSpec& arena, std::vector<Light>& lights);

}  // namespace stepstone::sim::tasks
