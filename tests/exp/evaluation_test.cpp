// Evaluations on threads (lib/exp/evaluation.cpp): evaluate_all gives genome k
// what evaluating it alone gives, its behaviour in its own slot, with any
// number of threads; parallel_for visits every index once and rethrows.
#include "exp/evaluation.hpp"

#include <atomic>
#include <catch2/catch.hpp>
#include <stdexcept>

#include "core/rng.hpp"
#include "nn/dnn_config.hpp"
#include "nn/genome.hpp"
#include "nn/mutation.hpp"
#include "sim/task.hpp"

using namespace stepstone;

namespace {

// The oracle: each genome evaluated alone (one network, one run_episode), one
// after the other. evaluate_all must give genome k the same evaluation and
// behaviour matrix, in its own slot, with every thread count in `threads`.
void require_evaluate_all_matches_alone(const sim::Task& task, const std::vector<nn::Genome>& genomes,
                                        const nn::DnnConfig& dnn, std::initializer_list<unsigned> threads) {
    const std::size_t width = task.behaviour_size();
    std::vector<exp::Evaluation> alone;
    std::vector<std::vector<float>> behaviours;
    for (const auto& genome : genomes) {
        behaviours.emplace_back(width);
        alone.push_back(exp::evaluate_genome(task, genome, dnn, behaviours.back()));
    }
    REQUIRE(behaviours[0] != behaviours[1]);  // distinct policies, so a swap would show

    for (unsigned thread_count : threads) {
        INFO(thread_count << " threads");
        std::vector<float> all;
        const auto results = exp::evaluate_all(task, genomes, dnn, thread_count, &all);
        REQUIRE(results.size() == genomes.size());
        REQUIRE(all.size() == genomes.size() * width);
        for (std::size_t k = 0; k < genomes.size(); ++k) {
            INFO("genome " << k);
            CHECK(results[k].reward == alone[k].reward);
            CHECK(results[k].balls == alone[k].balls);
            CHECK(results[k].steps == alone[k].steps);
            CHECK(results[k].nan_outputs == alone[k].nan_outputs);
            CHECK(results[k].milestones == alone[k].milestones);
            CHECK(results[k].cells == alone[k].cells);
            CHECK(std::equal(behaviours[k].begin(), behaviours[k].end(),
                             all.begin() + static_cast<std::ptrdiff_t>(k * width)));
        }
    }
}

}  // namespace

TEST_CASE("evaluate_all gives each genome its own evaluation and behaviour, whatever the thread count",
          "[exp][evaluation]") {
    sim::TaskConfig config;
    config.steps_per_start = 150;
    config.starts = 2;
    const auto task = sim::make_task(config);
    const nn::DnnConfig dnn;
    std::vector<nn::Genome> genomes;
    for (std::uint64_t k = 0; k < 6; ++k) {
        Rng rng(21, 0, k, Purpose::test);
        genomes.push_back(nn::Genome::random_perceptron(dnn, rng));
    }
    require_evaluate_all_matches_alone(*task, genomes, dnn, {1u, 3u});
}

TEST_CASE("policies evaluated in lanes, in batches of any size, equal their evaluations alone",
          "[exp][evaluation][lanes]") {
    // a population of mixed sizes: grown genomes with 0 to ~30 hidden neurons
    // (those above 24 are evaluated alone, the others in lanes, batched by
    // size), some stopped early by the stand-still rule in any start
    sim::TaskConfig config;
    config.steps_per_start = 300;
    config.starts = 3;
    config.still_limit = 60;
    const auto task = sim::make_task(config);
    nn::DnnConfig dnn;
    nn::DnnConfig growth = dnn;
    growth.add_connection_rate = 0.6;
    growth.add_neuron_rate = 0.5;
    std::vector<nn::Genome> genomes;
    for (std::uint64_t k = 0; k < 48; ++k) {
        Rng rng(22, 0, k, Purpose::test);
        nn::Genome genome = nn::Genome::random_perceptron(dnn, rng);
        for (std::uint64_t round = 0; round < k + k % 7 * 4; ++round) nn::mutate(genome, growth, rng);
        genomes.push_back(std::move(genome));
    }
    int large = 0;
    int stopped = 0;
    int full = 0;
    for (const auto& genome : genomes) large += genome.neuron_count() - 15 > 24 ? 1 : 0;
    for (const auto& genome : genomes) {
        const long steps = exp::evaluate_genome(*task, genome, dnn).steps;
        stopped += steps < 900 ? 1 : 0;
        full += steps == 900 ? 1 : 0;
    }
    REQUIRE(large >= 2);
    REQUIRE(large <= 16);
    REQUIRE(stopped >= 4);
    REQUIRE(full >= 4);
    // 1 thread: batches of 8; 3 threads: of 7 or so; 16 threads: too few a
    // thread for lanes, every genome alone
    require_evaluate_all_matches_alone(*task, genomes, dnn, {1u, 3u, 16u});
}

TEST_CASE("evaluate_all refuses a policy whose input or output count is not the task's",
          "[exp][evaluation]") {
    const auto task = sim::make_task(sim::TaskConfig{});
    for (const bool inputs : {true, false}) {
        nn::DnnConfig dnn;
        (inputs ? dnn.inputs : dnn.outputs) += 1;  // 13 inputs, or 4 outputs
        Rng rng(22, 0, 0, Purpose::test);
        const std::string expected = inputs
                                         ? "a policy of the task has 12 inputs and 3 outputs, not 13 and 3"
                                         : "a policy of the task has 12 inputs and 3 outputs, not 12 and 4";
        // one genome (evaluated alone) and three (in lanes)
        for (const std::size_t count : {1u, 3u}) {
            std::vector<nn::Genome> genomes;
            for (std::size_t k = 0; k < count; ++k)
                genomes.push_back(nn::Genome::random_perceptron(dnn, rng));
            REQUIRE_THROWS_WITH(exp::evaluate_all(*task, genomes, dnn, 1, nullptr), expected);
        }
    }
}

TEST_CASE("parallel_for calls the body once for every index and rethrows what a call threw",
          "[exp][evaluation]") {
    std::vector<std::atomic<int>> calls(100);
    exp::parallel_for(calls.size(), 4, [&](std::size_t k) { ++calls[k]; });
    for (std::size_t k = 0; k < calls.size(); ++k) CHECK(calls[k] == 1);
    exp::parallel_for(0, 4, [](std::size_t) { FAIL("no index to visit"); });
    CHECK_THROWS_WITH(exp::parallel_for(10, 3,
                                        [](std::size_t k) {
                                            if (k == 7) throw std::runtime_error("index 7 failed");
                                        }),
                      "index 7 failed");
    CHECK(exp::resolve_threads(5) == 5);
    CHECK(exp::resolve_threads(0) >= 1);
}
