// `episode`: whole evaluations, lib/sim + nn::Network against the bitmap
// simulator + the nn2-style pointer network.

#include <memory>
#include <vector>

#include "bench/cases.hpp"
#include "bench/spec_genome.hpp"
#include "core/error.hpp"
#include "exp/evaluation.hpp"
#include "nn/network.hpp"
#include "reference/fastsim_baseline.hpp"
#include "reference/pointer_network.hpp"
#include "sim/episode.hpp"
#include "sim/task.hpp"

namespace stepstone::bench {

using namespace stepstone::reference;  // the baselines

namespace {

constexpr long kEvaluationSteps = 12000;
// policies a call evaluates: one batch of lanes (nn::NetworkLanes::kLanes)
constexpr std::size_t kPolicies = 8;

// the policies as a run evaluates a population: exp::evaluate_all on one
// thread, which steps them together in lanes
struct CandidateEpisodes {
    std::shared_ptr<const sim::Task> task;
    std::vector<nn::Genome> genomes;
    std::vector<float> behaviours;

    std::uint64_t run() {
        exp::evaluate_all(*task, genomes, nn::DnnConfig{}, 1, &behaviours);
        return genomes.size();
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
        : arena(std::move(a)),
          episode(*arena, BitmapTask::source),
          network(spec),
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

    // networks that keep both robots moving for all 12,000 steps, so both
    // sides do whole evaluations (the stand-still rule would cut one short)
    std::vector<std::shared_ptr<BaselineEpisode>> baselines;
    auto candidate = std::make_shared<CandidateEpisodes>();
    candidate->task = task;
    for (std::uint64_t seed = 1; seed <= 256 && baselines.size() < kPolicies; ++seed) {
        const NetworkSpec spec = random_network_spec(12, 15, 3, 120, seed);
        auto baseline = std::make_shared<BaselineEpisode>(arena, spec);
        nn::Genome genome = genome_from_spec(spec);
        nn::Network network(genome, nn::DnnConfig{});
        check_same_network(baseline->network, network, 12, 3);
        baseline->run();
        const long steps = exp::evaluate_genome(*task, genome, nn::DnnConfig{}).steps;
        if (baseline->steps != kEvaluationSteps || steps != kEvaluationSteps) continue;
        baselines.push_back(std::move(baseline));
        candidate->genomes.push_back(std::move(genome));
    }
    if (baselines.size() < kPolicies) throw DataError("bench episode: too few random networks keep moving");
    const auto baseline_run = [baselines] {
        for (const auto& baseline : baselines) baseline->run();
        return static_cast<std::uint64_t>(baselines.size());
    };
    return Workload{baseline_run, [candidate] { return candidate->run(); }};
}

}  // namespace

void add_episode_cases(Registry& registry) {
    registry.add(
        Case{"episode", "evaluations",
             "8 12,000-step source evaluations with 12-15-3 networks and recording: exp::evaluate_all on "
             "1 thread (lanes) vs bitmap + pointer network, one after the other",
             14.0, make_episode_workload});
}

}  // namespace stepstone::bench
