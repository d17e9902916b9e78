// The target task (collectball's VARIANT_SW2, docs/original.md: objects): the door is
// open throughout, the only ball sits unlit at the arena's target_ball position
// (the paper's: top left, (97.5, 50.625)) and each switch press lights it; the
// switch re-arms 100 steps later.

#include "sim/tasks/tasks.hpp"

namespace stepstone::sim::tasks {

std::shared_ptr<const Task> make_target_task(const TaskConfig& config) {
    const ArenaSpec& arena = config.arena_spec();
    const Point& ball = arena.balls[arena.target_ball];
    std::vector<Light> lights{{LightKind::ball, ball.x, ball.y}};
    append_basket_and_switch(arena, lights);
    const auto count = static_cast<int>(lights.size());
    // the ball (bit 0) starts off; basket lights and switch on
    const std::uint32_t lit = ((1u << count) - 1u) & ~1u;
    return std::make_shared<const Task>(config, std::move(lights), lit, /*door_starts_open=*/true,
                                        /*switch_index=*/count - 1, /*spawn_ball_index=*/0);
}

}  // namespace stepstone::sim::tasks
