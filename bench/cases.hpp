#pragma once

// The case adders of bench/; default_registry() calls them in this order.

#include "bench/registry.hpp"

namespace stepstone::bench {

/// Calls every case adder.
void add_builtin_cases(Registry& registry);

/// `sim`: the candidate's sensor + motion step vs the bitmap baseline.
void add_sim_cases(Registry& registry);

/// `episode`: whole evaluations, lib/sim + nn::Network vs bitmap + pointer network.
void add_episode_cases(Registry& registry);

/// `nn`: network steps, nn::Network vs the pointer network.
void add_nn_cases(Registry& registry);

/// `diversity`: one generation's edit distances, lib/evo vs the original DP.
void add_diversity_cases(Registry& registry);

/// `evolve`: whole generations of the source task, 2 threads vs 1.
void add_evolve_cases(Registry& registry);

/// `evolved`: an evolved population's evaluations, portable math (lanes) vs libm.
void add_evolved_cases(Registry& registry);

/// `mpi`: evolve --mpi on 2 ranks vs 1 process on 2 threads (when built with Open MPI).
void add_mpi_cases(Registry& registry);

/// `render`: a trajectory figure with KB lookups vs replaying the policy.
void add_render_cases(Registry& registry);

/// `serve`: lookups over loopback HTTP vs in process, one row a client count
/// (serve/1, serve/2, serve/8).
void add_serve_cases(Registry& registry);

}  // namespace stepstone::bench
