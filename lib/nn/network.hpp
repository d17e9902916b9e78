#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "nn/dnn_config.hpp"
#include "nn/genome.hpp"

namespace stepstone::nn {

/// A Genome compiled to flat arrays for the episode loop (ORIGINAL.md 6.8):
/// one synchronous update per call of step(), every neuron reading the states
/// of the previous step (an input -> output edge acts within the step, each
/// hidden layer adds one step of delay).
///
/// Layout: states in one contiguous float array, indexed like the genome's
/// neurons; the incoming edges of each non-input neuron stored contiguously
/// (source index and float weight), in the genome's connection order. A step
/// computes every weighted sum into a second buffer, then applies the sigmoid
/// to the whole buffer in one vectorisable loop (fast_exp).
///
/// Arithmetic is float, weights and scaled biases rounded once from the
/// developed double values; sums run in the genome's connection order. The
/// result is deterministic and equals ReferenceNetwork bit for bit.
/// Inputs must be finite (the simulator validates its sensors).
///
/// A Network is a mutable evaluation state: use one per thread. Compiling is
/// cheap (a few hundred bytes), so each evaluation can own its network.
class Network {
public:
    /// An empty network (no neuron); step() must not be called on it.
    Network() = default;
    /// Compiles `genome` with the ranges and bias scale of `config`; every state is 0.
    Network(const Genome& genome, const DnnConfig& config);

    /// Sets every neuron state to 0 (nn2 init() at the start of each instance).
    void reset();
    /// One update: reads input_count() floats, writes output_count() floats
    /// (each in (0, 1)). `inputs` and `outputs` must not overlap the network.
    void step(const float* inputs, float* outputs);

    std::size_t input_count() const { return input_count_; }
    std::size_t output_count() const { return output_count_; }
    std::size_t neuron_count() const { return states_.size(); }
    std::size_t connection_count() const { return weights_.size(); }
    /// Current state of every neuron, indexed like the genome's neurons.
    std::span<const float> states() const { return states_; }

private:
    std::size_t input_count_ = 0;
    std::size_t output_count_ = 0;
    std::vector<float> states_;
    std::vector<float> scaled_biases_;     // per non-input neuron
    std::vector<float> sums_;              // per non-input neuron: the second buffer
    std::vector<std::uint32_t> offsets_;   // edges of non-input neuron k: [offsets_[k], offsets_[k + 1])
    std::vector<std::uint32_t> sources_;
    std::vector<float> weights_;
};

}  // namespace stepstone::nn
