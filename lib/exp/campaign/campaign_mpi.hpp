#pragma once

// `campaign --mpi`: a campaign's runs over the ranks of an MPI job. Rank 0
// runs run_campaign as ever (plan, campaign.db, the KB step) with an executor
// that hands each run, whole, to a free worker rank; a worker runs it in
// process (run_evolve) and reports how it ended. Each run file has one
// writer, its worker; campaign.db has one, rank 0.

#include <memory>

#include "exp/campaign/campaign_runner.hpp"
#include "exp/mpi_evolve.hpp"
#include "exp/parallel/mpi.hpp"

namespace stepstone::exp {

/// Rank 0's executor: one run per worker rank at a time (with a single
/// rank, rank 0 runs them itself). When mpirun ends the job under it (a rank
/// died), wait() throws Error naming the dead rank and its run; a job stopped
/// otherwise throws Interrupted (and abandons the leader's session).
std::unique_ptr<RunExecutor> make_mpi_executor(MpiLeader& leader);

/// A worker rank: runs what rank 0 hands out until it says stop. SIGINT and
/// SIGTERM are ignored: the job ends by rank 0's word or by mpirun.
void serve_campaign(mpi::Session& session);

}  // namespace stepstone::exp
