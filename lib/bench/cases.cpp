#include "bench/cases.hpp"

#if STEPSTONE_HAVE_KB_CASES
#include "bench/bench_kb.hpp"
#endif

namespace stepstone::bench {

void add_builtin_cases([[maybe_unused]] Registry& registry) {
#if STEPSTONE_HAVE_SIM
    add_sim_cases(registry);
#endif
#if STEPSTONE_HAVE_SIM && STEPSTONE_HAVE_NN
    add_episode_cases(registry);
#endif
#if STEPSTONE_HAVE_NN
    add_nn_cases(registry);
#endif
#if STEPSTONE_HAVE_EVO
    add_diversity_cases(registry);
#endif
#if STEPSTONE_HAVE_KB_CASES
    add_kb_cases(registry);
#endif
#if STEPSTONE_HAVE_EXP
    add_evolve_cases(registry);
    add_mpi_cases(registry);
#endif
#if STEPSTONE_HAVE_REPORT
    add_render_cases(registry);
#endif
#if STEPSTONE_HAVE_SERVICE
    add_serve_cases(registry);
#endif
}

}  // namespace stepstone::bench
