#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "nn/dnn_config.hpp"
#include "nn/genome.hpp"
#include "nn/network.hpp"

namespace stepstone::nn {

/// Up to kLanes networks stepped together, one per lane of a vector of 8
/// floats: the evaluation of several policies at once (docs/performance.md:
/// lanes of policies).
///
/// The networks may differ in hidden neurons and edges; they share the input
/// and output counts. Each is laid out as the dense Network is (one row per
/// input, then per hidden neuron; one column per output, then per hidden
/// neuron; 0 where there is no edge), padded to the largest of the batch, and
/// lane l holds network l's weights. A step adds x_row * w_row for the rows
/// in ascending order, as Network does, and applies the same sigmoid to each
/// lane, so lane l's outputs are those of Network(genomes[l]) bit for bit,
/// whatever its neighbours. A padding row or column adds 0 * x (x finite),
/// which leaves a float sum unchanged.
///
/// The cost of a step is that of the largest network for every lane, so a
/// batch is best made of networks of similar size (see lanes_cost()).
class NetworkLanes {
public:
    /// Networks per batch: the float lanes of an AVX register.
    static constexpr std::size_t kLanes = 8;

    /// Compiles `genomes` (1 to kLanes, with equal input and output counts)
    /// with the ranges and bias scale of `config`; every state is 0. `simd`
    /// only affects speed, never a result.
    NetworkLanes(std::span<const Genome* const> genomes, const DnnConfig& config,
                 Network::Simd simd = Network::Simd::automatic);

    /// Sets every neuron state of every lane to 0.
    void reset();
    /// Writes lane `lane`'s input_count() inputs for the next step.
    void set_inputs(std::size_t lane, const float* inputs);
    /// One update of every lane.
    void step();
    /// Reads lane `lane`'s output_count() outputs of the last step.
    void get_outputs(std::size_t lane, float* outputs) const;

    std::size_t lanes() const { return lanes_; }
    std::size_t input_count() const { return input_count_; }
    std::size_t output_count() const { return output_count_; }

    /// Vector multiply-adds of a step for a network of `hidden` hidden
    /// neurons, `inputs` inputs and `outputs` outputs (rows x columns).
    static std::size_t lanes_cost(std::size_t inputs, std::size_t outputs, std::size_t hidden) {
        return (inputs + hidden) * (outputs + hidden);
    }

private:
    std::size_t lanes_ = 0;
    std::size_t input_count_ = 0;
    std::size_t output_count_ = 0;
    std::size_t rows_ = 0;     // inputs + the largest hidden count
    std::size_t columns_ = 0;  // outputs + the largest hidden count
    bool avx2_ = false;
    std::vector<float> weights_;        // rows_ x columns_ x kLanes
    std::vector<float> scaled_biases_;  // columns_ x kLanes (padding 0)
    std::vector<float> states_;         // rows_ x kLanes: inputs, then hidden states
    std::vector<float> computed_;       // columns_ x kLanes: outputs, then hidden, after a step
};

}  // namespace stepstone::nn
