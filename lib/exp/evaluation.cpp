#include "exp/evaluation.hpp"

#include <algorithm>
#include <exception>
#include <thread>

#include "core/error.hpp"
#include "core/text.hpp"
#include "exp/parallel/writer_lock.hpp"
#include "nn/network.hpp"
#include "nn/network_lanes.hpp"
#include "sim/episode.hpp"

namespace stepstone::exp {

namespace {

// Genomes with more hidden neurons than this are evaluated alone: lanes pay
// their room's rows x columns in every lane.
constexpr std::size_t kLaneMaxHidden = 24;
// A queue shorter than this costs more in lanes than alone (every lane's
// vector work is paid whatever the lanes in use).
constexpr std::size_t kLaneMinQueue = 4;
// The longest queue of one work item: 4 genomes a lane, so that a thread's
// items stay of similar network sizes and the threads share the work.
constexpr std::size_t kLaneMaxQueue = 4 * nn::NetworkLanes::kLanes;

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

// The work items of evaluate_all: queues of genome indices evaluated in
// lanes, and single genomes. Genomes small enough for lanes are ordered by
// hidden-neuron count (then index), so a queue holds networks of similar
// size, and cut into queues of up to kLaneMaxQueue, shorter when several
// threads would not get two queues each. The plan only decides speed: every
// genome's evaluation is the same in a queue or alone.
std::vector<std::vector<std::size_t>> plan_work(std::span<const nn::Genome> genomes, unsigned threads) {
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
    const std::size_t per_queue = std::min(kLaneMaxQueue, std::max<std::size_t>(1, share));
    for (std::size_t first = 0; first < small.size(); first += per_queue) {
        const std::size_t count = std::min(per_queue, small.size() - first);
        if (count >= kLaneMinQueue) {
            items.emplace_back(small.begin() + static_cast<std::ptrdiff_t>(first),
                               small.begin() + static_cast<std::ptrdiff_t>(first + count));
        } else {
            for (std::size_t i = first; i < first + count; ++i) items.push_back({small[i]});
        }
    }
    return items;
}

// The episode reads 12 inputs and acts on 3 outputs: a genome with other counts is refused.
void check_counts(const nn::Genome& genome) {
    if (genome.input_count() != sim::kInputs || genome.output_count() != sim::kOutputs) {
        throw DataError(concat("a policy of the task has ", sim::kInputs, " inputs and ", sim::kOutputs,
                               " outputs, not ", genome.input_count(), " and ", genome.output_count()));
    }
}

// Evaluates genomes[queue] in lanes, each result in its own slot.
void evaluate_queue(const sim::Task& task, std::span<const nn::Genome> genomes,
                    std::span<const std::size_t> queue, const nn::DnnConfig& dnn,
                    std::vector<float>* behaviours, std::span<Evaluation> results) {
    std::size_t max_hidden = 0;
    for (std::size_t k : queue) max_hidden = std::max(max_hidden, hidden_count(genomes[k]));
    const nn::Genome& first = genomes[queue[0]];
    check_counts(first);  // NetworkLanes::load holds the queue's other genomes to the first's counts
    nn::NetworkLanes network(first.input_count(), first.output_count(), max_hidden, dnn);
    struct Controller {
        nn::NetworkLanes& network;
        std::span<const nn::Genome> genomes;
        std::span<const std::size_t> queue;
        std::size_t lanes() const { return network.lanes(); }
        void load(std::size_t lane, std::size_t job) { network.load(lane, genomes[queue[job]]); }
        void reset(std::size_t lane) { network.reset(lane); }
        // the counts checked above, known when compiling
        void set_inputs(std::size_t lane, const float* inputs) {
            network.set_inputs<sim::kInputs>(lane, inputs);
        }
        void step() { network.step(); }
        void get_outputs(std::size_t lane, float* outputs) const {
            network.get_outputs<sim::kOutputs>(lane, outputs);
        }
    } controller{network, genomes, queue};

    const std::size_t width = behaviours ? task.behaviour_size() : 0;
    const std::size_t cell_count = task.cell_count();
    // one cell buffer a lane would do; one a job keeps the bookkeeping plain
    std::vector<std::array<int, 2>> cells(queue.size() * cell_count);
    const auto recording_of = [&](std::size_t job) {
        sim::Recording recording;
        if (behaviours)
            recording.behaviour = std::span<float>(behaviours->data() + queue[job] * width, width);
        recording.cells = std::span(cells).subspan(job * cell_count, cell_count);
        return recording;
    };
    const auto done = [&](std::size_t job, const sim::EpisodeResult& result) {
        results[queue[job]] = to_evaluation(result, std::span(cells).subspan(job * cell_count, cell_count));
    };
    sim::run_episode_queue(task, controller, queue.size(), recording_of, done);
}

}  // namespace

Evaluation evaluate_genome(const sim::Task& task, const nn::Genome& genome, const nn::DnnConfig& dnn,
                           std::span<float> behaviour) {
    check_counts(genome);
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
    const auto items = plan_work(genomes, threads);
    parallel_for(items.size(), threads, [&](std::size_t i) {
        if (InterruptGuard::received()) return;  // abandoned: thrown below
        const std::vector<std::size_t>& item = items[i];
        if (item.size() > 1) return evaluate_queue(task, genomes, item, dnn, behaviours, results);
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
