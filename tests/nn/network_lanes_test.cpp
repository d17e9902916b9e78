// NetworkLanes (lib/nn/network_lanes.cpp): up to 8 networks stepped in the
// lanes of one vector. The oracle is ReferenceNetwork, the plain walk over
// the genome's graph, one network at a time.
#include "nn/network_lanes.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <memory>
#include <vector>

#include "core/error.hpp"
#include "nn/activation.hpp"
#include "reference/reference_network.hpp"
#include "support.hpp"

using namespace stepstone;
using namespace stepstone::nn;
using stepstone::reference::ReferenceNetwork;

namespace {

// Steps `genomes` in lanes (with each instruction set: AVX-512, AVX2 and the
// build target's, where the CPU has them) and each alone
// through ReferenceNetwork on the same inputs; every lane's outputs must be
// its reference's bit for bit at every step, across a reset.
void require_lanes_equal_references(const std::vector<Genome>& genomes, Rng& rng, int steps) {
    const DnnConfig config;
    std::vector<const Genome*> batch;
    for (const Genome& genome : genomes) batch.push_back(&genome);
    for (auto simd : {Network::Simd::automatic, Network::Simd::avx2, Network::Simd::baseline}) {
        NetworkLanes lanes(batch, config, simd);
        REQUIRE(lanes.lanes() == genomes.size());
        std::vector<std::unique_ptr<ReferenceNetwork>> references;
        for (const Genome& genome : genomes)
            references.push_back(std::make_unique<ReferenceNetwork>(genome, config));
        std::vector<float> inputs(12), expected(3), got(3);
        for (int step = 0; step < steps; ++step) {
            std::vector<std::vector<float>> all_inputs;
            for (std::size_t l = 0; l < genomes.size(); ++l) {
                for (auto& x : inputs) x = static_cast<float>(rng.uniform());
                all_inputs.push_back(inputs);
                lanes.set_inputs(l, inputs.data());
            }
            lanes.step();
            for (std::size_t l = 0; l < genomes.size(); ++l) {
                references[l]->step(all_inputs[l].data(), expected.data());
                lanes.get_outputs(l, got.data());
                INFO("lane " << l << " of " << genomes.size() << ", step " << step << ", hidden "
                             << genomes[l].neuron_count() - 15);
                REQUIRE(got == expected);
            }
            if (step == steps / 2) {
                lanes.reset();
                for (auto& reference : references) reference->reset();
            }
        }
    }
}

}  // namespace

TEST_CASE("fast_exp_lanes and sigmoid_lanes give every lane the scalar's bits", "[nn][activation]") {
    typedef float Lanes __attribute__((vector_size(8 * sizeof(float))));
    Rng rng(30);
    for (int trial = 0; trial < 2000; ++trial) {
        Lanes x;
        Lanes bias;
        for (int l = 0; l < 8; ++l) {
            // beyond both clamps, and the usual range
            x[l] = static_cast<float>(trial % 10 == 0 ? 200.0 * (rng.uniform() - 0.5)
                                                      : 30.0 * (rng.uniform() - 0.5));
            bias[l] = static_cast<float>(10.0 * (rng.uniform() - 0.5));
        }
        Lanes e = x;
        fast_exp_lanes(e);
        Lanes s = x;
        sigmoid_lanes(bias, s);
        for (int l = 0; l < 8; ++l) {
            REQUIRE(e[l] == fast_exp(x[l]));
            REQUIRE(s[l] == sigmoid(bias[l], x[l]));
        }
    }
}

TEST_CASE("each lane steps as its network alone would, whatever its neighbours", "[nn][network][lanes]") {
    Rng rng(31);
    int recurrent_batches = 0;
    for (int trial = 0; trial < 40; ++trial) {
        // 1 to 8 grown genomes of mixed sizes (hidden neurons, cycles, self-loops)
        const std::size_t count = 1 + static_cast<std::size_t>(trial) % 8;
        std::vector<Genome> genomes;
        for (std::size_t l = 0; l < count; ++l)
            genomes.push_back(nn_test::grown_genome(rng, 5 + (trial * 7 + static_cast<int>(l) * 13) % 50));
        for (const Genome& genome : genomes) recurrent_batches += genome.neuron_count() > 15 ? 1 : 0;
        require_lanes_equal_references(genomes, rng, 80);
    }
    CHECK(recurrent_batches > 100);  // most lanes had hidden neurons
}

TEST_CASE("batches of every column count, across the kernels' blocks of 12 and 18", "[nn][network][lanes]") {
    // the largest network of the batch sets the columns: 3 outputs + 0 to 30
    // hidden neurons, so every block tail of 1 to 11 (AVX2) and 1 to 17
    // (AVX-512) columns is met, and odd counts leave a sigmoid of one column
    // after the AVX-512 build's pairs
    Rng rng(32);
    for (std::size_t hidden = 0; hidden <= 30; ++hidden) {
        std::vector<Genome> genomes;
        genomes.push_back(nn_test::random_genome(rng, hidden, 0.3));
        for (int l = 1; l < 8; ++l) {
            genomes.push_back(nn_test::random_genome(rng, static_cast<std::size_t>(l) * hidden / 8, 0.3));
        }
        require_lanes_equal_references(genomes, rng, 20);
    }
}

TEST_CASE("a lane takes a new network while the others go on", "[nn][network][lanes]") {
    // lanes made with room for 10 hidden neurons; every few steps one lane
    // takes the next genome of a queue (its states 0) and must then step as
    // that genome's network alone from a reset, the other lanes undisturbed
    Rng rng(34);
    const DnnConfig config;
    std::vector<Genome> queue;
    for (int k = 0; k < 40; ++k)
        queue.push_back(nn_test::random_genome(rng, static_cast<std::size_t>(k % 11), 0.3));
    NetworkLanes lanes(12, 3, 10, config);
    REQUIRE(lanes.lanes() == NetworkLanes::kLanes);
    REQUIRE(lanes.max_hidden() == 10);
    std::vector<std::unique_ptr<ReferenceNetwork>> references(NetworkLanes::kLanes);
    std::size_t next = 0;
    for (std::size_t l = 0; l < NetworkLanes::kLanes; ++l) {
        lanes.load(l, queue[next]);
        references[l] = std::make_unique<ReferenceNetwork>(queue[next++], config);
    }
    std::vector<float> inputs(12), expected(3), got(3);
    for (int step = 0; step < 400; ++step) {
        if (step % 13 == 5 && next < queue.size()) {
            const std::size_t l = static_cast<std::size_t>(step) % NetworkLanes::kLanes;
            lanes.load(l, queue[next]);
            references[l] = std::make_unique<ReferenceNetwork>(queue[next++], config);
        }
        if (step % 29 == 11) {  // a new start of one lane
            const std::size_t l = static_cast<std::size_t>(step / 29) % NetworkLanes::kLanes;
            lanes.reset(l);
            references[l]->reset();
        }
        std::vector<std::vector<float>> all_inputs;
        for (std::size_t l = 0; l < NetworkLanes::kLanes; ++l) {
            for (auto& x : inputs) x = static_cast<float>(rng.uniform());
            all_inputs.push_back(inputs);
            lanes.set_inputs(l, inputs.data());
        }
        lanes.step();
        for (std::size_t l = 0; l < NetworkLanes::kLanes; ++l) {
            references[l]->step(all_inputs[l].data(), expected.data());
            lanes.get_outputs(l, got.data());
            INFO("lane " << l << ", step " << step);
            REQUIRE(got == expected);
        }
    }
    CHECK(next > 20);  // lanes were reloaded many times
    CHECK_THROWS_WITH(lanes.load(0, nn_test::random_genome(rng, 11, 0.3)),
                      Catch::Contains("11 hidden neurons does not fit lanes made for 10"));
}

TEST_CASE("a batch of networks is refused when empty, too large or of mixed shapes", "[nn][network][lanes]") {
    const DnnConfig config;
    Rng rng(33);
    const Genome a = nn_test::random_genome(rng, 2, 0.3);
    std::vector<const Genome*> none;
    CHECK_THROWS_AS(NetworkLanes(none, config), DataError);
    std::vector<const Genome*> nine(9, &a);
    CHECK_THROWS_WITH(NetworkLanes(nine, config), Catch::Contains("1 to 8 genomes, not 9"));
    const Genome other(10, 3);
    std::vector<const Genome*> mixed{&a, &other};
    CHECK_THROWS_WITH(NetworkLanes(mixed, config), Catch::Contains("same input and output counts"));
}
