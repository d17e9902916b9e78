// `evolve`: whole NSGA-II generations of the source task (evaluation,
// diversity, selection) on 2 threads against the same generations on 1.

#include <memory>

#include "bench/cases.hpp"
#include "exp/evolution.hpp"

namespace stepstone::bench {

namespace {

runs::EvolveConfig evolve_config(Size size) {
    runs::EvolveConfig config;
    config.seed = 3;
    if (size == Size::full) {
        // the paper's: population 200, 3 starts x 4000 steps
        config.ea.population_size = 200;
    } else {
        config.ea.population_size = 16;
        config.task.steps_per_start = 500;
        config.task.starts = 1;
    }
    return config;
}

// one side: its own run, advanced one epoch per call; both sides start from
// the same seed, so they evaluate the same genomes generation after generation
Work side(Size size, unsigned threads) {
    const auto config = evolve_config(size);
    auto evolution = std::make_shared<exp::Evolution>(config, *config.seed, threads);
    evolution->initialise();
    return [evolution] {
        const auto write = evolution->epoch();
        return static_cast<std::uint64_t>(write.stats.evaluations);
    };
}

}  // namespace

void add_evolve_cases(Registry& registry) {
    registry.add(
        Case{"evolve", "evaluations",
             "one source-task generation (population 200, 12,000 steps an evaluation, diversity, selection): "
             "2 threads vs 1",
             1.8, [](Size size) {
                 return Workload{side(size, 1), side(size, 2)};
             }});
}

}  // namespace stepstone::bench
