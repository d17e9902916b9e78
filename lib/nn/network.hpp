#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "nn/dnn_config.hpp"
#include "nn/genome.hpp"

namespace stepstone::nn {

/// Whether this CPU runs AVX2 (the vector kernels' faster build; x86-64 only).
bool cpu_has_avx2();

/// A Genome compiled to flat arrays for the episode loop (docs/original.md: network):
/// one synchronous update per call of step(), every neuron reading the states
/// of the previous step (an input -> output edge acts within the step, each
/// hidden layer adds one step of delay).
///
/// Every weighted sum runs over its incoming edges in ascending source
/// order, in float, starting from 0; the sums go to a second buffer, then the
/// sigmoid (fast_exp) is applied to the whole buffer in one vectorisable
/// loop. Two layouts compute exactly these sums:
/// - dense (small networks, the usual case): a weight matrix with one row per
///   source neuron and the targets padded to a multiple of 8, zero where there
///   is no edge. A step adds x_source * row to the target sums, one source
///   after the other, across the targets in vector lanes. A missing edge adds
///   0 * x, which leaves a float sum unchanged (states are finite), so the
///   result is that of the edge list.
/// - sparse (large, thin networks): the incoming edges of each target stored
///   contiguously (source index and weight), walked one by one.
///
/// Weights and scaled biases are rounded once to float from the developed
/// double values. Both layouts give the same bits as each other and as
/// ReferenceNetwork (reference/reference_network.hpp), on any run and thread. Inputs must be finite (the
/// simulator validates its sensors).
///
/// A Network is a mutable evaluation state: use one per thread. Compiling is
/// cheap (microseconds; the dense matrix is at most 128 KiB), so each
/// evaluation can own its network.
class Network {
public:
    /// How the weights are stored; `automatic` picks the faster for the shape.
    enum class Layout : std::uint8_t { automatic, dense, sparse };
    /// Vector instructions of the step: `automatic` uses the widest the CPU
    /// has and core/cpu.hpp allows (AVX-512 where NetworkLanes has a build for
    /// it, AVX2), `avx2` at most AVX2, `baseline` only those of the build
    /// target (SSE2 on x86-64). Every choice gives the same bits.
    enum class Simd : std::uint8_t { automatic, avx2, baseline };

    /// An empty network (no neuron); step() must not be called on it.
    Network() = default;
    /// Compiles `genome` with the ranges and bias scale of `config`; every
    /// state is 0. `layout` and `simd` only affect speed, never a result.
    Network(const Genome& genome, const DnnConfig& config, Layout layout = Layout::automatic,
            Simd simd = Simd::automatic);

    /// Sets every neuron state to 0 (nn2 init() at the start of each instance).
    void reset();
    /// One update: reads input_count() floats, writes output_count() floats
    /// (each in (0, 1)). `inputs` and `outputs` must not overlap the network.
    void step(const float* inputs, float* outputs);

    std::size_t input_count() const { return input_count_; }
    std::size_t output_count() const { return output_count_; }
    std::size_t neuron_count() const { return neuron_count_; }
    std::size_t connection_count() const { return connection_count_; }
    /// The layout chosen at construction (dense or sparse; never automatic).
    Layout layout() const { return layout_; }
    /// Whether step() runs its AVX2 build (chosen at construction).
    bool uses_avx2() const { return avx2_; }
    /// Current state of every neuron, indexed like the genome's neurons.
    std::span<const float> states() const { return {states_.data(), neuron_count_}; }

    /// Targets per block of the dense layout (the padding of the target count).
    static constexpr std::size_t kBlock = 8;

private:
    void compile_dense(const Genome& genome, const DnnConfig& config);
    void compile_sparse(const Genome& genome, const DnnConfig& config);
    void dense_sums();
    void sparse_sums();

    std::size_t input_count_ = 0;
    std::size_t output_count_ = 0;
    std::size_t neuron_count_ = 0;
    std::size_t connection_count_ = 0;
    std::size_t padded_ = 0;               // non-input neurons rounded up to kBlock
    Layout layout_ = Layout::dense;
    bool avx2_ = false;
    std::vector<float> states_;            // input_count_ + padded_: inputs, then computed neurons
    std::vector<float> scaled_biases_;     // per non-input neuron, padded_ (padding 0)
    std::vector<float> sums_;              // per non-input neuron, padded_: the second buffer
    // dense: one row per input and hidden neuron (the possible sources), one
    // column per target, stored in groups of up to 32 targets, row by row
    std::vector<float> matrix_;
    // sparse: edges of non-input neuron k are [offsets_[k], offsets_[k + 1])
    std::vector<std::uint32_t> offsets_;
    std::vector<std::uint32_t> sources_;
    std::vector<float> weights_;
};

}  // namespace stepstone::nn
