#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "evo/edit_distance.hpp"
#include "nn/dnn_config.hpp"
#include "nn/genome.hpp"
#include "sim/episode.hpp"
#include "sim/task.hpp"

namespace stepstone::exp {

/// What one evaluation of a genome on a task gives.
struct Evaluation {
    double reward = 0;       ///< task reward (balls / 24 by default)
    int balls = 0;
    long steps = 0;          ///< simulation steps run
    int nan_outputs = 0;     ///< network outputs that were NaN (replaced by 0)
    sim::Milestones milestones;  ///< steps of the task reached, all starts
    evo::Trajectory cells;   ///< diversity trajectory of the first start
    std::optional<double> r_max;  ///< shaping from a knowledge base, when the run has one
};

/// Compiles `genome` and runs one evaluation. `behaviour`, if not empty,
/// receives the first start's behaviour matrix (Task::behaviour_size()
/// floats). Deterministic and thread-safe (the task is shared read-only).
Evaluation evaluate_genome(const sim::Task& task, const nn::Genome& genome, const nn::DnnConfig& dnn,
                           std::span<float> behaviour = {});

/// Thrown by evaluate_all when SIGINT or SIGTERM arrived under an
/// InterruptGuard (exp/parallel/writer_lock.hpp): the evaluations were abandoned.
struct EvaluationInterrupted {
    /// Empty for a user's stop; otherwise what went wrong (a rank of an MPI
    /// job died), reported as an error.
    std::string reason;
};

/// Evaluates every genome on `threads` threads (0 = all cores). Result k
/// belongs to genome k whatever the thread count. If `behaviours` is not
/// null it is resized to genomes.size() x behaviour_size() and filled.
/// Under an InterruptGuard, a signal abandons the remaining evaluations
/// (EvaluationInterrupted), so a stop never waits for a whole generation.
std::vector<Evaluation> evaluate_all(const sim::Task& task, std::span<const nn::Genome> genomes,
                                     const nn::DnnConfig& dnn, unsigned threads,
                                     std::vector<float>* behaviours = nullptr);

/// Threads to use for `requested` (0 = every core of the machine).
unsigned resolve_threads(unsigned requested);

/// Calls body(k) for every k in [0, count) on `threads` threads (0 = every
/// core), indices handed out one at a time. `body` must write only what
/// belongs to index k, so the result does not depend on the thread count.
/// The first exception a call throws is rethrown once every thread stopped.
void parallel_for(std::size_t count, unsigned threads, const std::function<void(std::size_t)>& body);

}  // namespace stepstone::exp
