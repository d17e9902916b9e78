#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "core/aligned.hpp"
#include "core/assert.hpp"
#include "nn/dnn_config.hpp"
#include "nn/genome.hpp"
#include "nn/network.hpp"

namespace stepstone::nn {

/// Up to kLanes networks stepped together, one per lane of a vector of 8
/// floats: the evaluation of several policies at once (docs/performance.md:
/// episode, lanes).
///
/// The networks may differ in hidden neurons and edges; they share the input
/// and output counts. Each is laid out as the dense Network is (one row per
/// input, then per hidden neuron; one column per output, then per hidden
/// neuron; 0 where there is no edge), padded to the room the lanes were made
/// with, and lane l holds network l's weights. A step adds x_row * w_row for
/// the rows in ascending order, as Network does, and applies the same sigmoid
/// to each lane, so lane l's outputs are those of Network(genome l) bit for
/// bit, whatever its neighbours. A padding row or column adds 0 * x (x
/// finite), which leaves a float sum unchanged.
///
/// A step costs rows x columns vector multiply-adds for all lanes, so lanes
/// are best filled with networks of similar size. A lane can take a new
/// network at any time (load()), the others going on.
class NetworkLanes {
public:
    /// Networks at once: the float lanes of an AVX register.
    static constexpr std::size_t kLanes = 8;

    /// Room for kLanes networks of `inputs` inputs, `outputs` outputs and at
    /// most `max_hidden` hidden neurons, compiled with the ranges and bias
    /// scale of `config`; every lane empty (no edge) and every state 0.
    /// `simd` only affects speed, never a result.
    NetworkLanes(std::size_t inputs, std::size_t outputs, std::size_t max_hidden, const DnnConfig& config,
                 Network::Simd simd = Network::Simd::automatic);
    /// `genomes` (1 to kLanes, with equal input and output counts) in lanes 0
    /// to genomes.size() - 1, with room for the largest; lanes() is their count.
    NetworkLanes(std::span<const Genome* const> genomes, const DnnConfig& config,
                 Network::Simd simd = Network::Simd::automatic);

    /// Puts `genome` in lane `lane`, its states 0. Throws DataError when its
    /// input or output count differs or it has more hidden neurons than the room.
    void load(std::size_t lane, const Genome& genome);
    /// Sets every neuron state of every lane to 0.
    void reset();
    /// Sets every neuron state of lane `lane` to 0.
    void reset(std::size_t lane);
    /// Writes lane `lane`'s input_count() inputs for the next step.
    void set_inputs(std::size_t lane, const float* inputs) {
        STEPSTONE_ASSERT(lane < lanes_);
        for (std::size_t i = 0; i < input_count_; ++i) states_[i * kLanes + lane] = inputs[i];
    }
    /// set_inputs() with input_count() known when compiling (N): a loop without a trip count to test.
    template <std::size_t N>
    void set_inputs(std::size_t lane, const float* inputs) {
        STEPSTONE_ASSERT(lane < lanes_ && N == input_count_);
        for (std::size_t i = 0; i < N; ++i) states_[i * kLanes + lane] = inputs[i];
    }
    /// One update of every lane.
    void step();
    /// Reads lane `lane`'s output_count() outputs of the last step.
    void get_outputs(std::size_t lane, float* outputs) const {
        STEPSTONE_ASSERT(lane < lanes_);
        for (std::size_t o = 0; o < output_count_; ++o) outputs[o] = computed_[o * kLanes + lane];
    }
    /// get_outputs() with output_count() known when compiling (N).
    template <std::size_t N>
    void get_outputs(std::size_t lane, float* outputs) const {
        STEPSTONE_ASSERT(lane < lanes_ && N == output_count_);
        for (std::size_t o = 0; o < N; ++o) outputs[o] = computed_[o * kLanes + lane];
    }

    /// Lanes in use: kLanes, or the genomes' count for the second constructor.
    std::size_t lanes() const { return lanes_; }
    std::size_t input_count() const { return input_count_; }
    std::size_t output_count() const { return output_count_; }
    /// The most hidden neurons a lane's network may have.
    std::size_t max_hidden() const { return rows_ - input_count_; }

private:
    DnnConfig config_;
    std::size_t lanes_ = 0;
    std::size_t input_count_ = 0;
    std::size_t output_count_ = 0;
    std::size_t rows_ = 0;     // inputs + the room for hidden neurons
    std::size_t columns_ = 0;  // outputs + the room for hidden neurons
    bool avx2_ = false;
    bool avx512_ = false;
    // (on cache lines: the kernels load one or two columns' lanes at a time, 32 or 64 bytes)
    CacheAlignedVector<float> weights_;        // rows_ x columns_ x kLanes
    CacheAlignedVector<float> scaled_biases_;  // columns_ x kLanes (padding 0)
    CacheAlignedVector<float> states_;         // rows_ x kLanes: inputs, then hidden states
    CacheAlignedVector<float> computed_;       // columns_ x kLanes: outputs, then hidden, after a step
};

}  // namespace stepstone::nn
