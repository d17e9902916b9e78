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
#include "sim/task.hpp"

using namespace stepstone;

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
    // the oracle: each genome evaluated alone, one after the other
    const std::size_t width = task->behaviour_size();
    std::vector<exp::Evaluation> alone;
    std::vector<std::vector<float>> behaviours;
    for (const auto& genome : genomes) {
        behaviours.emplace_back(width);
        alone.push_back(exp::evaluate_genome(*task, genome, dnn, behaviours.back()));
    }
    REQUIRE(behaviours[0] != behaviours[1]);  // distinct policies, so a swap would show

    for (unsigned threads : {1u, 3u}) {
        INFO(threads << " threads");
        std::vector<float> all;
        const auto results = exp::evaluate_all(*task, genomes, dnn, threads, &all);
        REQUIRE(results.size() == genomes.size());
        REQUIRE(all.size() == genomes.size() * width);
        for (std::size_t k = 0; k < genomes.size(); ++k) {
            INFO("genome " << k);
            CHECK(results[k].reward == alone[k].reward);
            CHECK(results[k].steps == alone[k].steps);
            CHECK(results[k].milestones == alone[k].milestones);
            CHECK(results[k].cells == alone[k].cells);
            CHECK(std::equal(behaviours[k].begin(), behaviours[k].end(),
                             all.begin() + static_cast<std::ptrdiff_t>(k * width)));
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
