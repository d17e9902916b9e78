#include "bench/cases.hpp"

#include "bench/bench_kb.hpp"
#include "bench/bench_shaped.hpp"

namespace stepstone::bench {

void add_builtin_cases(Registry& registry) {
    add_sim_cases(registry);
    add_episode_cases(registry);
    add_nn_cases(registry);
    add_diversity_cases(registry);
    add_kb_cases(registry);
    add_shaped_cases(registry);
    add_evolve_cases(registry);
    add_evolved_cases(registry);
    add_mpi_cases(registry);
    add_render_cases(registry);
    add_serve_cases(registry);
}

}  // namespace stepstone::bench
