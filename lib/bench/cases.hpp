#pragma once

// The case adders of lib/bench. Each one exists only when its candidate module
// is built (STEPSTONE_HAVE_<MODULE>, set in lib/bench/CMakeLists.txt);
// default_registry() calls those that exist, in this order.

#include "bench/registry.hpp"

namespace stepstone::bench {

/// Calls every case adder compiled into this library.
void add_builtin_cases(Registry& registry);

#if STEPSTONE_HAVE_SIM
/// `sim`: the candidate's sensor + motion step vs the bitmap baseline.
void add_sim_cases(Registry& registry);
#endif

#if STEPSTONE_HAVE_SIM && STEPSTONE_HAVE_NN
/// `episode`: whole evaluations, lib/sim + nn::Network vs bitmap + pointer network.
void add_episode_cases(Registry& registry);
#endif

#if STEPSTONE_HAVE_NN
/// `nn`: network steps, nn::Network vs the pointer network.
void add_nn_cases(Registry& registry);
#endif

#if STEPSTONE_HAVE_EVO
/// `diversity`: one generation's edit distances, lib/evo vs the original DP.
void add_diversity_cases(Registry& registry);
#endif

#if STEPSTONE_HAVE_EXP
/// `evolve`: whole generations of the source task, 2 threads vs 1.
void add_evolve_cases(Registry& registry);
#endif

#if STEPSTONE_HAVE_EXP
/// `mpi`: evolve --mpi on 2 ranks vs 1 process on 2 threads (when built with Open MPI).
void add_mpi_cases(Registry& registry);
#endif

#if STEPSTONE_HAVE_REPORT
/// `render`: a trajectory figure with KB lookups vs replaying the policy.
void add_render_cases(Registry& registry);
#endif

#if STEPSTONE_HAVE_SERVICE
/// `serve`, `serve-2`, `serve-8`: lookups over loopback HTTP vs in process.
void add_serve_cases(Registry& registry);
#endif

}  // namespace stepstone::bench
