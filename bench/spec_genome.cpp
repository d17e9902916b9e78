#include "bench/spec_genome.hpp"

#include <cmath>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/rng.hpp"
#include "nn/network.hpp"

namespace stepstone::bench {

using namespace stepstone::reference;  // the baselines

nn::Genome genome_from_spec(const NetworkSpec& spec, const nn::DnnConfig& config) {
    nn::Genome genome(static_cast<std::size_t>(spec.inputs), static_cast<std::size_t>(spec.outputs));
    for (int h = 0; h < spec.hidden; ++h) genome.add_hidden(0.5);
    const auto gene = [](double value, double lo, double hi) { return (value - lo) / (hi - lo); };
    for (std::size_t i = 0; i < spec.biases.size(); ++i) {
        genome.biases()[i] = gene(spec.biases[i], config.bias_min, config.bias_max);
    }
    for (const auto& e : spec.edges) {
        genome.add_connection(static_cast<std::size_t>(e.source), static_cast<std::size_t>(e.target),
                              gene(e.weight, config.weight_min, config.weight_max));
    }
    return genome;
}

void check_same_network(PointerNetwork& baseline, nn::Network& candidate, int inputs, int outputs) {
    Rng rng(5);
    std::vector<float> in(static_cast<std::size_t>(inputs));
    std::vector<float> a(static_cast<std::size_t>(outputs));
    std::vector<float> b(static_cast<std::size_t>(outputs));
    for (int trial = 0; trial < 100; ++trial) {
        baseline.reset();
        candidate.reset();
        for (int step = 0; step < 3; ++step) {
            for (float& v : in) v = static_cast<float>(rng.uniform());
            baseline.step(in.data(), a.data());
            candidate.step(in.data(), b.data());
            for (std::size_t k = 0; k < a.size(); ++k) {
                if (!(std::fabs(a[k] - b[k]) <= 1e-4f)) {
                    throw DataError("bench: pointer network and nn::Network differ at step " +
                                    std::to_string(step) + ": " + std::to_string(a[k]) + " vs " +
                                    std::to_string(b[k]));
                }
            }
        }
    }
    baseline.reset();
    candidate.reset();
}

}  // namespace stepstone::bench
