#include "nn/network.hpp"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <thread>
#include <vector>

#include "nn/activation.hpp"
#include "reference/reference_network.hpp"
#include "support.hpp"

using namespace stepstone;
using namespace stepstone::nn;
using stepstone::reference::ReferenceNetwork;

namespace {

bool has_cycle_edge(const Genome& genome) {
    // a self-loop or an edge from a later hidden neuron back to an earlier one
    const std::size_t first_hidden = genome.input_count() + genome.output_count();
    for (const auto& c : genome.connections()) {
        if (c.source >= first_hidden && c.target >= first_hidden && c.source >= c.target) return true;
    }
    return false;
}

// the network in every layout and instruction set it can run with
std::vector<Network> all_layouts(const Genome& genome, const DnnConfig& config) {
    std::vector<Network> nets;
    for (auto layout : {Network::Layout::automatic, Network::Layout::dense, Network::Layout::sparse}) {
        for (auto simd : {Network::Simd::automatic, Network::Simd::baseline}) nets.emplace_back(genome, config, layout, simd);
    }
    return nets;
}

}  // namespace

TEST_CASE("fast_exp agrees with std::exp to float precision", "[nn][activation]") {
    double worst = 0.0;
    for (double x = -87.0; x <= 88.0; x += 0.001) {
        const double want = std::exp(x);
        const double got = fast_exp(static_cast<float>(x));
        worst = std::max(worst, std::abs(got - std::exp(double(static_cast<float>(x)))) / want);
    }
    // a few float ulps (2^-23 = 1.2e-7)
    CHECK(worst < 4e-7);
    // clamping keeps extreme arguments finite and ordered
    CHECK(fast_exp(-1000.0f) > 0.0f);
    CHECK(std::isfinite(fast_exp(1000.0f)));
}

TEST_CASE("the activation is nn2's sigmoid with the bias scaled by 5", "[nn][activation]") {
    // one input, one output, weight gene 1 -> w = 5, bias gene 0.5 -> b = 0
    Genome genome(1, 1);
    genome.add_connection(0, 1, 1.0);
    Network net(genome, DnnConfig{});
    float in = 0.0f, out = 0.0f;
    net.step(&in, &out);
    CHECK(out == 0.5f);  // 1 / (1 + exp(0))
    in = 1.0f;
    net.step(&in, &out);
    CHECK(out == Approx(0.9933071490757153).epsilon(1e-6));  // 1 / (1 + e^-5)

    // bias gene 1 -> b = 5, scaled 25: y = 1 / (1 + exp(25 - 5 x)) at x = 1 is 1 / (1 + e^20)
    genome.biases()[1] = 1.0;
    Network biased(genome, DnnConfig{});
    biased.step(&in, &out);
    CHECK(out == Approx(2.0611536181902037e-09).epsilon(1e-5));
}

TEST_CASE("each hidden layer delays the signal by one step", "[nn][network]") {
    // 0 -> 2 -> 1 with w = 5 and b = 0 everywhere (docs/original.md: network)
    Genome genome(1, 1);
    genome.add_hidden(0.5);
    genome.add_connection(0, 2, 1.0);
    genome.add_connection(2, 1, 1.0);
    Network net(genome, DnnConfig{});
    const float in = 1.0f;
    float out = 0.0f;
    net.step(&in, &out);
    CHECK(out == 0.5f);  // the hidden state was still 0
    net.step(&in, &out);
    const double hidden = 1.0 / (1.0 + std::exp(-5.0));
    CHECK(out == Approx(1.0 / (1.0 + std::exp(-5.0 * hidden))).epsilon(1e-6));

    // reset brings back the first-step output
    net.reset();
    net.step(&in, &out);
    CHECK(out == 0.5f);
}

TEST_CASE("a neuron without inputs outputs its constant", "[nn][network]") {
    // 1 / (1 + exp(5 b)) with bias gene 0.6 -> b = 1: 1 / (1 + e^5)
    Genome genome(1, 1);
    genome.biases()[1] = 0.6;
    Network net(genome, DnnConfig{});
    const float in = 0.7f;
    float out = 0.0f;
    net.step(&in, &out);
    CHECK(out == Approx(0.0066928509242848554).epsilon(1e-5));
}

TEST_CASE("every layout of the flat network equals the reference graph walk bit for bit", "[nn][network]") {
    Rng rng(21);
    const DnnConfig config;
    int recurrent = 0;
    for (int trial = 0; trial < 150; ++trial) {
        Genome genome = nn_test::grown_genome(rng, 10 + trial % 60);
        if (trial % 2 == 0) genome.simplify();
        recurrent += has_cycle_edge(genome);
        std::vector<Network> flat = all_layouts(genome, config);
        ReferenceNetwork reference(genome, config);
        std::vector<float> inputs(12), reference_out(3);
        std::vector<std::vector<float>> flat_out(flat.size(), std::vector<float>(3));
        for (int step = 0; step < 300; ++step) {
            for (auto& x : inputs) x = static_cast<float>(rng.uniform());
            reference.step(inputs.data(), reference_out.data());
            for (std::size_t k = 0; k < flat.size(); ++k) {
                flat[k].step(inputs.data(), flat_out[k].data());
                REQUIRE(flat_out[k] == reference_out);
            }
            if (step == 150) {
                for (auto& net : flat) net.reset();
                reference.reset();
            }
        }
    }
    CHECK(recurrent > 30);  // the comparison covered recurrent genomes
}

TEST_CASE("wide networks span several groups of targets and still equal the reference", "[nn][network]") {
    // 10 to 90 hidden neurons: the dense matrix holds 1 to 4 groups of up to
    // 32 targets, with every partial group width of 8, 16, 24 and 32
    Rng rng(23);
    const DnnConfig config;
    for (int trial = 0; trial < 24; ++trial) {
        const std::size_t hidden = 10 + static_cast<std::size_t>(trial) * 7 % 81;
        const Genome genome = nn_test::random_genome(rng, hidden, 0.05 + 0.3 * rng.uniform());
        std::vector<Network> flat = all_layouts(genome, config);
        ReferenceNetwork reference(genome, config);
        std::vector<float> inputs(12), reference_out(3), out(3);
        for (int step = 0; step < 60; ++step) {
            for (auto& x : inputs) x = static_cast<float>(rng.uniform());
            reference.step(inputs.data(), reference_out.data());
            for (auto& net : flat) {
                net.step(inputs.data(), out.data());
                REQUIRE(out == reference_out);
            }
        }
        // the hidden states agree too, not only the outputs
        for (auto& net : flat) {
            REQUIRE(net.neuron_count() == genome.neuron_count());
            REQUIRE(std::equal(net.states().begin(), net.states().end(), flat[0].states().begin()));
        }
    }
}

TEST_CASE("the network does not depend on the order in which connections were added", "[nn][network]") {
    // sums run in ascending source order whatever the genome's connection order
    Rng rng(24);
    const DnnConfig config;
    for (int trial = 0; trial < 30; ++trial) {
        const Genome genome = nn_test::grown_genome(rng, 20 + trial);
        Genome reversed(genome.input_count(), genome.output_count());
        for (std::size_t n = 0; n < genome.hidden_count(); ++n) reversed.add_hidden(0.5);
        reversed.biases() = genome.biases();
        for (auto c = genome.connections().rbegin(); c != genome.connections().rend(); ++c) {
            reversed.add_connection(c->source, c->target, c->weight);
        }
        Network a(genome, config), b(reversed, config);
        std::vector<float> inputs(12), out_a(3), out_b(3);
        for (int step = 0; step < 100; ++step) {
            for (auto& x : inputs) x = static_cast<float>(rng.uniform());
            a.step(inputs.data(), out_a.data());
            b.step(inputs.data(), out_b.data());
            REQUIRE(out_a == out_b);
        }
    }
}

TEST_CASE("two runs of a network give the same bits, on any thread", "[nn][network][determinism]") {
    Rng rng(25);
    const DnnConfig config;
    const Genome genome = nn_test::grown_genome(rng, 60);
    std::vector<float> inputs(12 * 500);
    for (auto& x : inputs) x = static_cast<float>(rng.uniform());
    const auto run = [&](Network& net) {
        std::vector<float> outputs(3 * 500);
        net.reset();
        for (std::size_t s = 0; s < 500; ++s) net.step(inputs.data() + 12 * s, outputs.data() + 3 * s);
        return outputs;
    };
    Network net(genome, config);
    const std::vector<float> first = run(net);
    CHECK(run(net) == first);  // reset() restores the initial state exactly
    Network other(genome, config);
    CHECK(run(other) == first);
    std::vector<float> on_thread;
    std::thread([&] {
        Network mine(genome, config);
        on_thread = run(mine);
    }).join();
    CHECK(on_thread == first);
}

TEST_CASE("small networks get the dense layout and large thin ones the sparse one", "[nn][network]") {
    Rng rng(26);
    const DnnConfig config;
    // the initial perceptron and the benchmark's 12-15-3 shape
    const Genome perceptron = Genome::random_perceptron(config, rng);
    CHECK(Network(perceptron, config).layout() == Network::Layout::dense);
    CHECK(Network(nn_test::random_genome(rng, 15, 0.35), config).layout() == Network::Layout::dense);
    // 150 hidden neurons with about one edge in a hundred pairs
    CHECK(Network(nn_test::random_genome(rng, 150, 0.01), config).layout() == Network::Layout::sparse);
    // a forced layout is kept
    CHECK(Network(perceptron, config, Network::Layout::sparse).layout() == Network::Layout::sparse);
    CHECK(!Network(perceptron, config, Network::Layout::dense, Network::Simd::baseline).uses_avx2());
}

TEST_CASE("the float network stays close to nn2's double sigmoid", "[nn][network]") {
    Rng rng(22);
    const DnnConfig config;
    double worst = 0.0;
    for (int trial = 0; trial < 40; ++trial) {
        const Genome genome = nn_test::grown_genome(rng, 15);
        Network flat(genome, config);
        ReferenceNetwork exact(genome, config, true);
        std::vector<float> inputs(12), a(3), b(3);
        for (int step = 0; step < 100; ++step) {
            for (auto& x : inputs) x = static_cast<float>(rng.uniform());
            flat.step(inputs.data(), a.data());
            exact.step(inputs.data(), b.data());
            for (int k = 0; k < 3; ++k) worst = std::max(worst, double(std::abs(a[k] - b[k])));
        }
    }
    // differences start at float rounding and pass through at most a few layers
    CHECK(worst < 1e-4);
}
