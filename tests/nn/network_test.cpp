#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "nn/activation.hpp"
#include "nn/network.hpp"
#include "nn/reference_network.hpp"
#include "support.hpp"

using namespace stepstone;
using namespace stepstone::nn;

namespace {

bool has_cycle_edge(const Genome& genome) {
    // a self-loop or an edge from a later hidden neuron back to an earlier one
    const std::size_t first_hidden = genome.input_count() + genome.output_count();
    for (const auto& c : genome.connections()) {
        if (c.source >= first_hidden && c.target >= first_hidden && c.source >= c.target) return true;
    }
    return false;
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
    // 0 -> 2 -> 1 with w = 5 and b = 0 everywhere (ORIGINAL.md 6.8)
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

TEST_CASE("the flat network equals the reference graph walk bit for bit", "[nn][network]") {
    Rng rng(21);
    const DnnConfig config;
    int recurrent = 0;
    for (int trial = 0; trial < 150; ++trial) {
        Genome genome = nn_test::grown_genome(rng, 10 + trial % 60);
        if (trial % 2 == 0) genome.simplify();
        recurrent += has_cycle_edge(genome);
        Network flat(genome, config);
        ReferenceNetwork reference(genome, config);
        std::vector<float> inputs(12), flat_out(3), reference_out(3);
        for (int step = 0; step < 300; ++step) {
            for (auto& x : inputs) x = static_cast<float>(rng.uniform());
            flat.step(inputs.data(), flat_out.data());
            reference.step(inputs.data(), reference_out.data());
            REQUIRE(flat_out == reference_out);
            if (step == 150) {
                flat.reset();
                reference.reset();
            }
        }
    }
    CHECK(recurrent > 30);  // the comparison covered recurrent genomes
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
