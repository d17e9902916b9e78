// The source task (collectball's default build, docs/original.md: objects): eight
// lit balls, four of them in the left room behind a closed door; pressing the
// switch opens the door until the next start.

#include "sim/tasks/tasks.hpp"

namespace stepstone::sim::tasks {

std::shared_ptr<const Task> make_source_task(const TaskConfig& config) {
    std::vector<Light> lights(kBalls.begin(), kBalls.end());
    lights.insert(lights.end(), kBasketLights.begin(), kBasketLights.end());
    lights.push_back(kSwitch);
    const auto count = static_cast<int>(lights.size());
    const std::uint32_t all_lit = (1u << count) - 1u;
    return std::make_shared<const Task>(config, std::move(lights), all_lit, /*door_starts_open=*/false,
                                        /*switch_index=*/count - 1, /*spawn_ball_index=*/-1);
}

}  // namespace stepstone::sim::tasks
