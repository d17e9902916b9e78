#include "exp/evaluation.hpp"

#include "core/writer_lock.hpp"

#include <algorithm>
#include <exception>
#include <thread>

#include "nn/network.hpp"
#include "sim/episode.hpp"

namespace stepstone::exp {

Evaluation evaluate_genome(const sim::Task& task, const nn::Genome& genome, const nn::DnnConfig& dnn,
                           std::span<float> behaviour) {
    nn::Network network(genome, dnn);
    std::vector<std::array<int, 2>> cells(task.cell_count());
    sim::Recording recording;
    recording.behaviour = behaviour;
    recording.cells = cells;
    const sim::EpisodeResult result = sim::run_episode(task, network, recording);

    Evaluation evaluation;
    evaluation.reward = result.reward;
    evaluation.balls = result.balls;
    evaluation.steps = result.steps_run;
    evaluation.nan_outputs = result.nan_outputs;
    evaluation.milestones = result.milestones;
    evaluation.cells.reserve(cells.size());
    for (const auto& cell : cells) {
        evaluation.cells.push_back({static_cast<std::int16_t>(cell[0]), static_cast<std::int16_t>(cell[1])});
    }
    return evaluation;
}

unsigned resolve_threads(unsigned requested) {
    if (requested > 0) return requested;
    const unsigned cores = std::thread::hardware_concurrency();
    return cores > 0 ? cores : 1;
}

std::vector<Evaluation> evaluate_all(const sim::Task& task, std::span<const nn::Genome> genomes,
                                     const nn::DnnConfig& dnn, unsigned threads, std::vector<float>* behaviours) {
    std::vector<Evaluation> results(genomes.size());
    const std::size_t width = behaviours ? task.behaviour_size() : 0;
    // no zero fill: every evaluation writes its whole matrix (an early stop pads it), and a
    // buffer kept from the last call keeps its pages
    if (behaviours) behaviours->resize(genomes.size() * width);
    parallel_for(genomes.size(), threads, [&](std::size_t k) {
        if (InterruptGuard::received()) return;  // abandoned: thrown below
        std::span<float> behaviour;
        if (behaviours) behaviour = std::span<float>(behaviours->data() + k * width, width);
        results[k] = evaluate_genome(task, genomes[k], dnn, behaviour);
    });
    if (InterruptGuard::received()) throw EvaluationInterrupted{};
    return results;
}

void parallel_for(std::size_t count, unsigned threads, const std::function<void(std::size_t)>& body) {
    // OpenMP hands out indices; each call writes only its own slot
    std::exception_ptr failure;
    const auto n = static_cast<int>(count);
    const int thread_count = static_cast<int>(std::min<std::size_t>(resolve_threads(threads), count));
#pragma omp parallel for schedule(dynamic, 1) num_threads(thread_count > 0 ? thread_count : 1)
    for (int i = 0; i < n; ++i) {
        try {
            body(static_cast<std::size_t>(i));
        } catch (...) {
#pragma omp critical(stepstone_parallel_for_failure)
            if (!failure) failure = std::current_exception();
        }
    }
    if (failure) std::rethrow_exception(failure);
}

}  // namespace stepstone::exp
