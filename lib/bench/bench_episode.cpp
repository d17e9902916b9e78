// `episode`: whole evaluations, lib/sim + nn::Network against the bitmap
// simulator + the nn2-style pointer network.

#include <memory>
#include <vector>

#include "bench/cases.hpp"
#include "bench/fastsim_baseline.hpp"
#include "bench/pointer_network.hpp"
#include "bench/spec_genome.hpp"
#include "nn/network.hpp"
#include "sim/episode.hpp"
#include "sim/task.hpp"

namespace stepstone::bench {

namespace {

constexpr long kEvaluationSteps = 12000;

struct CandidateEpisode {
    std::shared_ptr<const sim::Task> task;
    nn::Network network;
    std::vector<float> behaviour;
    std::vector<std::array<int, 2>> cells;
    long steps = 0;

    std::uint64_t run() {
        const auto result = sim::run_episode(*task, network, sim::Recording{behaviour, cells, nullptr});
        steps = result.steps_run;
        return 1;
    }
};

struct BaselineEpisode {
    std::shared_ptr<const BitmapArena> arena;
    BitmapCollectBall episode;
    PointerNetwork network;
    std::vector<float> behaviour;
    std::vector<std::int32_t> cells;
    long steps = 0;

    BaselineEpisode(std::shared_ptr<const BitmapArena> a, const NetworkSpec& spec)
        : arena(std::move(a)), episode(*arena, BitmapTask::source), network(spec),
          behaviour(BitmapCollectBall::kStepsPerStart * BitmapCollectBall::kChannels),
          cells(BitmapCollectBall::kCells * 2) {}

    std::uint64_t run() {
        const auto result = run_bitmap_episode(episode, network, BitmapRecording{behaviour, cells});
        steps = result.steps;
        return 1;
    }
};

Workload make_episode_workload(Size) {
    auto arena = std::make_shared<const BitmapArena>();
    auto task = sim::make_task(sim::TaskConfig{});

    // a network that keeps both robots moving for all 12,000 steps, so both
    // sides do whole evaluations (the stand-still rule would cut one short)
    std::shared_ptr<BaselineEpisode> baseline;
    std::shared_ptr<CandidateEpisode> candidate;
    for (std::uint64_t seed = 1; seed <= 64; ++seed) {
        const NetworkSpec spec = random_network_spec(12, 15, 3, 120, seed);
        baseline = std::make_shared<BaselineEpisode>(arena, spec);
        candidate = std::make_shared<CandidateEpisode>();
        candidate->task = task;
        candidate->network = nn::Network(genome_from_spec(spec), nn::DnnConfig{});
        candidate->behaviour.resize(task->behaviour_size());
        candidate->cells.resize(task->cell_count());
        check_same_network(baseline->network, candidate->network, 12, 3);
        baseline->run();
        candidate->run();
        if (baseline->steps == kEvaluationSteps && candidate->steps == kEvaluationSteps) break;
    }
    return Workload{[baseline] { return baseline->run(); }, [candidate] { return candidate->run(); }};
}

}  // namespace

void add_episode_cases(Registry& registry) {
    registry.add(Case{"episode", "evaluations",
                      "12,000-step source evaluations with a 12-15-3 network and recording: lib/sim + nn vs bitmap + "
                      "pointer network",
                      8.0, make_episode_workload});
}

}  // namespace stepstone::bench
