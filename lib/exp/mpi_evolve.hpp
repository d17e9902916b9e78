#pragma once

// `evolve --mpi`: one run's evaluations spread over the ranks of an MPI job.
// Rank 0 runs run_evolve as ever (selection, the run's KB, the run file);
// each generation it hands the genomes out in small chunks to the ranks that
// are free, evaluates one at a time itself while it waits, and puts every
// result in its individual's slot, so the run is the same for any number of
// ranks. The diversity's new edit distances are shared the same way, in
// chunks of pairs. The other ranks serve until rank 0 says stop.

#include <memory>
#include <string>

#include "exp/evolution.hpp"
#include "exp/parallel/mpi.hpp"

namespace stepstone::exp {

/// Message tags of `evolve --mpi` and `campaign --mpi`.
enum MpiTag : int {
    kTagSetup = 1,      ///< rank 0 -> worker: what to do (a run's config, a run to carry out)
    kTagWork = 2,       ///< rank 0 -> worker: genomes to evaluate
    kTagResult = 3,     ///< worker -> rank 0: their evaluations, or a run's end
    kTagFailure = 4,    ///< worker -> rank 0: an error, one line
    kTagStop = 5,       ///< rank 0 -> worker: finish and leave
    kTagPairs = 6,      ///< rank 0 -> worker: pairs of trajectories (and the trajectories, once a generation)
    kTagDistances = 7,  ///< worker -> rank 0: the distances of those pairs
};

/// Rank 0's side of `evolve --mpi`. Whatever happens, the other ranks are
/// told to stop when it goes (unless the job is lost: abandon()).
class MpiLeader {
public:
    /// Sends and receives of `session` give up (mpi::Cancelled) once SIGINT
    /// or SIGTERM arrived under an InterruptGuard: mpirun ending the job.
    explicit MpiLeader(mpi::Session& session);
    ~MpiLeader();
    MpiLeader(const MpiLeader&) = delete;
    MpiLeader& operator=(const MpiLeader&) = delete;

    /// Sends the run's effective config (`config`, its shaping KB's path and
    /// digest included) to the other ranks and returns the evaluator that
    /// hands them each generation. `shaping` is the run's shaping KB (null
    /// without one); `run` names the run file in messages.
    std::unique_ptr<RemoteEvaluator> start(const runs::EvolveConfig& config, const kb::KnowledgeBase* shaping,
                                           const std::string& run);
    /// The job is ending without the other ranks: no stop messages, no MPI_Finalize.
    void abandon();
    /// Called when mpirun is ending the job under rank 0 (a signal arrived):
    /// abandons, and returns "rank R (pid P on HOST) died" for the ranks of
    /// this host that died; empty when none did (the job was cancelled, or a
    /// rank on another host was lost).
    std::string lose();

    mpi::Session& session() { return session_; }

private:
    mpi::Session& session_;
    bool abandoned_ = false;
};

/// A worker rank of `evolve --mpi`: waits for rank 0's config, then
/// evaluates the genomes it sends on `threads` threads until it says stop.
/// A failure is sent to rank 0 as one line (rank 0 reports it and stops). SIGINT and SIGTERM
/// are ignored: a job ends by rank 0's word, or by mpirun killing it.
void serve_evolve(mpi::Session& session, unsigned threads);

}  // namespace stepstone::exp
