#include "nn/network.hpp"

#include <algorithm>

#include "core/assert.hpp"
#include "nn/activation.hpp"
#include "nn/reference_network.hpp"

namespace stepstone::nn {

Network::Network(const Genome& genome, const DnnConfig& config)
    : input_count_(genome.input_count()),
      output_count_(genome.output_count()),
      states_(genome.neuron_count(), 0.0f) {
    const std::size_t computed = genome.neuron_count() - input_count_;
    scaled_biases_.resize(computed);
    sums_.assign(computed, 0.0f);
    for (std::size_t k = 0; k < computed; ++k) {
        scaled_biases_[k] = developed_scaled_bias(genome.biases()[input_count_ + k], config);
    }

    // counting sort of the edges by target, stable: sums keep the genome's order
    offsets_.assign(computed + 1, 0);
    for (const auto& c : genome.connections()) ++offsets_[c.target - input_count_ + 1];
    for (std::size_t k = 0; k < computed; ++k) offsets_[k + 1] += offsets_[k];
    sources_.resize(genome.connection_count());
    weights_.resize(genome.connection_count());
    std::vector<std::uint32_t> fill(offsets_.begin(), offsets_.end() - 1);
    for (const auto& c : genome.connections()) {
        const std::uint32_t slot = fill[c.target - input_count_]++;
        sources_[slot] = c.source;
        weights_[slot] = developed_weight(c.weight, config);
    }
}

void Network::reset() { std::fill(states_.begin(), states_.end(), 0.0f); }

void Network::step(const float* inputs, float* outputs) {
    STEPSTONE_ASSERT(!states_.empty());
    float* const states = states_.data();
    std::copy(inputs, inputs + input_count_, states);

    // weighted sums from the previous states, into the second buffer
    const std::size_t computed = sums_.size();
    const std::uint32_t* const offsets = offsets_.data();
    const std::uint32_t* const sources = sources_.data();
    const float* const weights = weights_.data();
    float* const sums = sums_.data();
    for (std::size_t k = 0; k < computed; ++k) {
        float sum = 0.0f;
        for (std::uint32_t e = offsets[k]; e < offsets[k + 1]; ++e) sum += weights[e] * states[sources[e]];
        sums[k] = sum;
    }

    // every sigmoid at once: one branch-free loop the compiler vectorises
    const float* const biases = scaled_biases_.data();
    float* const computed_states = states + input_count_;
    for (std::size_t k = 0; k < computed; ++k) computed_states[k] = sigmoid(biases[k], sums[k]);

    std::copy(computed_states, computed_states + output_count_, outputs);
}

}  // namespace stepstone::nn
