// The source task (collectball's default build, docs/original.md: objects): every
// ball lit (the paper's arena: eight, four of them in the left room behind a
// closed door); pressing the switch opens the door until the next start.

#include "sim/tasks/tasks.hpp"

namespace stepstone::sim::tasks {

void append_basket_and_switch(const ArenaSpec& arena, std::vector<Light>& lights) {
    for (const Point& p : arena.basket.lights) lights.push_back({LightKind::basket, p.x, p.y});
    lights.push_back({LightKind::switch_light, arena.switch_light.x, arena.switch_light.y});
}

std::shared_ptr<const Task> make_source_task(const TaskConfig& config) {
    const ArenaSpec& arena = config.arena_spec();
    std::vector<Light> lights;
    for (const Point& p : arena.balls) lights.push_back({LightKind::ball, p.x, p.y});
    append_basket_and_switch(arena, lights);
    const auto count = static_cast<int>(lights.size());
    const std::uint32_t all_lit = (1u << count) - 1u;
    return std::make_shared<const Task>(config, std::move(lights), all_lit, /*door_starts_open=*/false,
                                        /*switch_index=*/count - 1, /*spawn_ball_index=*/-1);
}

}  // namespace stepstone::sim::tasks
