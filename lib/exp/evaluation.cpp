#include "exp/evaluation.hpp"

#include <algorithm>
#include <exception>
#include <thread>

#include "core/writer_lock.hpp"
#include "nn/network.hpp"
#include "nn/network_lanes.hpp"
#include "sim/episode.hpp"

namespace stepstone::exp {

namespace {

// Genomes with more hidden neurons than this are evaluated alone: a batch
// pays its largest network's rows x columns in every lane.
constexpr std::size_t kLaneMaxHidden = 24;
// Fewer policies than this in a batch cost more in lanes than alone (every
// lane's vector work is paid whatever the lanes in use).
constexpr std::size_t kLaneMinBatch = 4;

Evaluation to_evaluation(const sim::EpisodeResult& result, std::span<const std::array<int, 2>> cells) {
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

std::size_t hidden_count(const nn::Genome& genome) {
    return genome.neuron_count() - genome.input_count() - genome.output_count();
}

// The work items of evaluate_all: batches of genome indices evaluated in
// lanes, and single genomes. Genomes small enough for lanes are ordered by
// hidden-neuron count (then index), so a batch holds networks of similar
// size, and cut into batches of up to 8, fewer when several threads would
// not get two batches each. The plan only decides speed: every genome's evaluation
// is the same in a batch or alone.
std::vector<std::vector<std::size_t>> plan_batches(std::span<const nn::Genome> genomes, unsigned threads) {
    std::vector<std::size_t> small;
    std::vector<std::vector<std::size_t>> items;
    for (std::size_t k = 0; k < genomes.size(); ++k) {
        if (hidden_count(genomes[k]) <= kLaneMaxHidden) {
            small.push_back(k);
        } else {
            items.push_back({k});
        }
    }
    std::stable_sort(small.begin(), small.end(), [&](std::size_t a, std::size_t b) {
        return hidden_count(genomes[a]) < hidden_count(genomes[b]);
    });
    const unsigned thread_count = resolve_threads(threads);
    const std::size_t share = thread_count == 1 ? small.size() : small.size() / (2 * thread_count);
    const std::size_t per_batch = std::min(nn::NetworkLanes::kLanes, std::max<std::size_t>(1, share));
    for (std::size_t first = 0; first < small.size(); first += per_batch) {
        const std::size_t count = std::min(per_batch, small.size() - first);
        if (count >= kLaneMinBatch) {
            items.emplace_back(small.begin() + static_cast<std::ptrdiff_t>(first),
                               small.begin() + static_cast<std::ptrdiff_t>(first + count));
        } else {
            for (std::size_t i = first; i < first + count; ++i) items.push_back({small[i]});
        }
    }
    return items;
}

// Evaluates genomes[indices] in lanes, each result in its own slot.
void evaluate_batch(const sim::Task& task, std::span<const nn::Genome> genomes,
                    std::span<const std::size_t> indices, const nn::DnnConfig& dnn,
                    std::vector<float>* behaviours, std::span<Evaluation> results) {
    std::vector<const nn::Genome*> batch;
    for (std::size_t k : indices) batch.push_back(&genomes[k]);
    nn::NetworkLanes network(batch, dnn);
    const std::size_t width = behaviours ? task.behaviour_size() : 0;
    std::vector<std::array<int, 2>> cells(indices.size() * task.cell_count());
    std::vector<sim::Recording> recordings(indices.size());
    for (std::size_t l = 0; l < indices.size(); ++l) {
        if (behaviours)
            recordings[l].behaviour = std::span<float>(behaviours->data() + indices[l] * width, width);
        recordings[l].cells = std::span(cells).subspan(l * task.cell_count(), task.cell_count());
    }
    const auto outcomes = sim::run_episodes(task, network, recordings);
    for (std::size_t l = 0; l < indices.size(); ++l) {
        results[indices[l]] = to_evaluation(outcomes[l], recordings[l].cells);
    }
}

}  // namespace

Evaluation evaluate_genome(const sim::Task& task, const nn::Genome& genome, const nn::DnnConfig& dnn,
                           std::span<float> behaviour) {
    nn::Network network(genome, dnn);
    std::vector<std::array<int, 2>> cells(task.cell_count());
    sim::Recording recording;
    recording.behaviour = behaviour;
    recording.cells = cells;
    return to_evaluation(sim::run_episode(task, network, recording), cells);
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
    const auto items = plan_batches(genomes, threads);
    parallel_for(items.size(), threads, [&](std::size_t i) {
        if (InterruptGuard::received()) return;  // abandoned: thrown below
        const std::vector<std::size_t>& item = items[i];
        if (item.size() > 1) return evaluate_batch(task, genomes, item, dnn, behaviours, results);
        const std::size_t k = item[0];
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
