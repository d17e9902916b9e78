#pragma once

// helpers shared by the nn tests: random genomes with hidden neurons and
// recurrence, and the graph invariants every genome must keep

#include <set>
#include <utility>

#include <catch2/catch.hpp>

#include "core/rng.hpp"
#include "nn/genome.hpp"
#include "nn/mutation.hpp"

namespace nn_test {

using stepstone::Rng;
using stepstone::nn::DnnConfig;
using stepstone::nn::Genome;

// a perceptron grown by `rounds` mutations with raised structural rates, so
// genomes get hidden neurons, cycles and self-loops
inline Genome grown_genome(Rng& rng, int rounds, const DnnConfig& base = DnnConfig{}) {
    DnnConfig config = base;
    config.add_connection_rate = 0.6;
    config.add_neuron_rate = 0.3;
    config.delete_neuron_rate = 0.05;
    config.delete_connection_rate = 0.1;
    config.rewire_connection_rate = 0.05;
    Genome genome = Genome::random_perceptron(config, rng);
    for (int r = 0; r < rounds; ++r) stepstone::nn::mutate(genome, config, rng);
    return genome;
}

// 12 inputs, 3 outputs, `hidden` hidden neurons; each valid pair connected
// with probability `density`; random genes
inline Genome random_genome(Rng& rng, std::size_t hidden, double density) {
    Genome genome(12, 3);
    for (std::size_t n = 0; n < hidden; ++n) genome.add_hidden(rng.uniform());
    for (auto& bias : genome.biases()) bias = rng.uniform();
    for (std::size_t source = 0; source < genome.neuron_count(); ++source) {
        if (!genome.can_be_source(source)) continue;
        for (std::size_t target = 12; target < genome.neuron_count(); ++target) {
            if (rng.bernoulli(density)) genome.add_connection(source, target, rng.uniform());
        }
    }
    return genome;
}

inline void require_invariants(const Genome& genome) {
    std::set<std::pair<std::uint32_t, std::uint32_t>> seen;
    for (const auto& c : genome.connections()) {
        REQUIRE(c.source < genome.neuron_count());
        REQUIRE(c.target < genome.neuron_count());
        // no edge out of an output, none into an input
        REQUIRE(genome.kind(c.source) != stepstone::nn::NeuronKind::output);
        REQUIRE(genome.kind(c.target) != stepstone::nn::NeuronKind::input);
        REQUIRE(seen.emplace(c.source, c.target).second);  // no duplicate
        REQUIRE(c.weight >= 0.0);
        REQUIRE(c.weight <= 1.0);
    }
    for (double bias : genome.biases()) {
        REQUIRE(bias >= 0.0);
        REQUIRE(bias <= 1.0);
    }
}

}  // namespace nn_test
