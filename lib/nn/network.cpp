#include "nn/network.hpp"

#include <algorithm>
#include <cstring>

#include "core/assert.hpp"
#include "core/cpu.hpp"
#include "nn/activation.hpp"

#if defined(__x86_64__) || defined(__i386__)
#define STEPSTONE_NN_HAVE_AVX2_KERNEL 1
#endif

namespace stepstone::nn {

namespace {

// Targets summed together in one pass over the sources: up to 4 blocks of 8
// (32 accumulators, which stay in vector registers).
constexpr std::size_t kGroupBlocks = 4;
constexpr std::size_t kGroup = kGroupBlocks * Network::kBlock;

// The dense layout is chosen while its matrix has at most this many cells
// per edge: measured break-even points are ~20 with AVX2 and ~8 with SSE2
// (vs one scalar multiply-add and an indexed load per sparse edge). The cap
// keeps the matrix within a typical L2 cache (128 KiB).
constexpr std::size_t kDenseCellsPerEdgeAvx2 = 16;
constexpr std::size_t kDenseCellsPerEdgeBaseline = 6;
constexpr std::size_t kDenseMaxCells = 32768;

std::size_t round_up(std::size_t n, std::size_t multiple) { return (n + multiple - 1) / multiple * multiple; }

// Float lanes (GCC/Clang vector extension) with plain lane-wise IEEE
// arithmetic: 4 lanes fill an SSE register, 8 an AVX one.
typedef float Lanes4 __attribute__((vector_size(4 * sizeof(float))));
typedef float Lanes8 __attribute__((vector_size(8 * sizeof(float))));

// The vector part of a dense step. The matrix has one row per possible
// source: the inputs, then the hidden neurons (outputs feed no neuron), so
// row r reads a state at a fixed place and needs no index.
struct DenseStep {
    const float* input_states;   // input_count states
    std::size_t input_count;
    const float* hidden_states;  // hidden_count states
    std::size_t hidden_count;
    const float* matrix;         // group after group, each row by row
    const float* scaled_biases;  // padded
    float* sums;                 // padded
    float* computed_states;      // padded: outputs, hidden neurons, padding
    std::size_t padded;          // a multiple of Network::kBlock
};

// acc[v] += x * w[v] across the vectors of one row.
template <class Lanes, std::size_t Vectors>
[[gnu::always_inline]] inline void add_row(Lanes (&acc)[Vectors], float x, const float* w) {
    constexpr std::size_t kLanes = sizeof(Lanes) / sizeof(float);
#pragma GCC unroll 8
    for (std::size_t v = 0; v < Vectors; ++v) {
        Lanes weights;
        std::memcpy(&weights, w + v * kLanes, sizeof weights);
        acc[v] += x * weights;
    }
}

// Sums of one group of `Blocks` x kBlock targets: for each source row in
// turn, sums[t] += x * w[t] across the group's targets, the accumulators held
// in registers. Every lane adds its terms in row order (ascending source
// index), whatever the vector width.
template <class Lanes, std::size_t Blocks>
[[gnu::always_inline]] inline void group_sums(const DenseStep& s, const float* matrix, float* sums) {
    constexpr std::size_t kLanes = sizeof(Lanes) / sizeof(float);
    constexpr std::size_t kWidth = Blocks * Network::kBlock;
    constexpr std::size_t kVectors = kWidth / kLanes;
    Lanes acc[kVectors] = {};
    const float* w = matrix;
    for (std::size_t i = 0; i < s.input_count; ++i, w += kWidth) add_row(acc, s.input_states[i], w);
    for (std::size_t h = 0; h < s.hidden_count; ++h, w += kWidth) add_row(acc, s.hidden_states[h], w);
    // one store per vector, so that the loads of the sigmoid loop are forwarded
#pragma GCC unroll 8
    for (std::size_t v = 0; v < kVectors; ++v) std::memcpy(sums + v * kLanes, &acc[v], sizeof acc[v]);
}

template <class Lanes>
[[gnu::always_inline]] inline void dense_sums(const DenseStep& s) {
    const std::size_t rows = s.input_count + s.hidden_count;
    for (std::size_t start = 0; start < s.padded; start += kGroup) {
        const float* const matrix = s.matrix + start * rows;
        float* const sums = s.sums + start;
        switch ((s.padded - start) / Network::kBlock) {
            case 1: group_sums<Lanes, 1>(s, matrix, sums); break;
            case 2: group_sums<Lanes, 2>(s, matrix, sums); break;
            case 3: group_sums<Lanes, 3>(s, matrix, sums); break;
            default: group_sums<Lanes, 4>(s, matrix, sums); break;
        }
    }
}

// Every sigmoid at once, the padding included: one branch-free loop the
// compiler vectorises, with no remainder (`padded` is a multiple of kBlock).
[[gnu::always_inline]] inline void sigmoids(const float* __restrict scaled_biases, const float* __restrict sums,
                                            float* __restrict states, std::size_t padded) {
    for (std::size_t k = 0; k < padded; ++k) states[k] = sigmoid(scaled_biases[k], sums[k]);
}

// The vector code is built twice from the same source: for baseline x86-64
// (SSE2) and for AVX2, picked at construction. Neither contracts a multiply
// and an add (-ffp-contract=off, and the AVX2 build has no FMA) and every
// lane does the same IEEE operations, so both compute the same bits.
void dense_step_baseline(const DenseStep& s) {
    dense_sums<Lanes4>(s);
    sigmoids(s.scaled_biases, s.sums, s.computed_states, s.padded);
}

void sigmoids_baseline(const float* scaled_biases, const float* sums, float* states, std::size_t padded) {
    sigmoids(scaled_biases, sums, states, padded);
}

#ifdef STEPSTONE_NN_HAVE_AVX2_KERNEL
[[gnu::target("avx2")]] void dense_step_avx2(const DenseStep& s) {
    dense_sums<Lanes8>(s);
    sigmoids(s.scaled_biases, s.sums, s.computed_states, s.padded);
}

[[gnu::target("avx2")]] void sigmoids_avx2(const float* scaled_biases, const float* sums, float* states,
                                           std::size_t padded) {
    sigmoids(scaled_biases, sums, states, padded);
}
#endif

void dense_step(const DenseStep& s, [[maybe_unused]] bool avx2) {
#ifdef STEPSTONE_NN_HAVE_AVX2_KERNEL
    if (avx2) return dense_step_avx2(s);
#endif
    dense_step_baseline(s);
}

void sigmoid_step(const float* scaled_biases, const float* sums, float* states, std::size_t padded,
                  [[maybe_unused]] bool avx2) {
#ifdef STEPSTONE_NN_HAVE_AVX2_KERNEL
    if (avx2) return sigmoids_avx2(scaled_biases, sums, states, padded);
#endif
    sigmoids_baseline(scaled_biases, sums, states, padded);
}

}  // namespace

bool cpu_has_avx2() {
#ifdef STEPSTONE_NN_HAVE_AVX2_KERNEL
    return avx2_kernels_allowed();
#else
    return false;
#endif
}

Network::Network(const Genome& genome, const DnnConfig& config, Layout layout, Simd simd)
    : input_count_(genome.input_count()),
      output_count_(genome.output_count()),
      neuron_count_(genome.neuron_count()),
      connection_count_(genome.connection_count()) {
    const std::size_t computed = neuron_count_ - input_count_;
    padded_ = round_up(computed, kBlock);
    states_.assign(input_count_ + padded_, 0.0f);
    sums_.assign(padded_, 0.0f);
    scaled_biases_.assign(padded_, 0.0f);
    for (std::size_t k = 0; k < computed; ++k) {
        scaled_biases_[k] = developed_scaled_bias(genome.biases()[input_count_ + k], config);
    }

    avx2_ = simd != Simd::baseline && cpu_has_avx2();
    if (layout == Layout::automatic) {
        // one row per input and hidden neuron (outputs are never sources)
        const std::size_t cells = (neuron_count_ - output_count_) * padded_;
        const std::size_t per_edge = avx2_ ? kDenseCellsPerEdgeAvx2 : kDenseCellsPerEdgeBaseline;
        const bool dense = cells <= kDenseMaxCells && cells <= per_edge * connection_count_;
        layout = dense ? Layout::dense : Layout::sparse;
    }
    layout_ = layout;
    if (layout_ == Layout::dense) {
        compile_dense(genome, config);
    } else {
        compile_sparse(genome, config);
    }
}

void Network::compile_dense(const Genome& genome, const DnnConfig& config) {
    // rows: the inputs, then the hidden neurons; 0 where there is no edge
    const std::size_t rows = neuron_count_ - output_count_;
    matrix_.assign(rows * padded_, 0.0f);
    for (const auto& c : genome.connections()) {
        STEPSTONE_ASSERT(genome.can_be_source(c.source));
        const std::size_t row = c.source < input_count_ ? c.source : c.source - output_count_;
        const std::size_t target = c.target - input_count_;
        const std::size_t group_start = target / kGroup * kGroup;
        const std::size_t width = std::min(kGroup, padded_ - group_start);
        matrix_[group_start * rows + row * width + (target - group_start)] = developed_weight(c.weight, config);
    }
}

void Network::compile_sparse(const Genome& genome, const DnnConfig& config) {
    // edges grouped by target (counting sort), each group in ascending source order
    std::vector<Connection> edges = genome.connections();
    std::sort(edges.begin(), edges.end(),
              [](const Connection& a, const Connection& b) { return a.source < b.source; });
    const std::size_t computed = neuron_count_ - input_count_;
    offsets_.assign(computed + 1, 0);
    for (const auto& c : edges) ++offsets_[c.target - input_count_ + 1];
    for (std::size_t k = 0; k < computed; ++k) offsets_[k + 1] += offsets_[k];
    sources_.resize(edges.size());
    weights_.resize(edges.size());
    std::vector<std::uint32_t> fill(offsets_.begin(), offsets_.end() - 1);
    for (const auto& c : edges) {
        const std::uint32_t slot = fill[c.target - input_count_]++;
        sources_[slot] = c.source;
        weights_[slot] = developed_weight(c.weight, config);
    }
}

void Network::reset() { std::fill(states_.begin(), states_.end(), 0.0f); }

void Network::sparse_sums() {
    const float* const states = states_.data();
    const std::uint32_t* const offsets = offsets_.data();
    const std::uint32_t* const sources = sources_.data();
    const float* const weights = weights_.data();
    float* const sums = sums_.data();
    const std::size_t computed = offsets_.size() - 1;
    for (std::size_t k = 0; k < computed; ++k) {
        float sum = 0.0f;
        for (std::uint32_t e = offsets[k]; e < offsets[k + 1]; ++e) sum += weights[e] * states[sources[e]];
        sums[k] = sum;
    }
}

void Network::step(const float* inputs, float* outputs) {
    STEPSTONE_ASSERT(neuron_count_ > 0);
    float* const states = states_.data();
    float* const computed_states = states + input_count_;
    for (std::size_t i = 0; i < input_count_; ++i) states[i] = inputs[i];

    // the weighted sums from the previous states into the second buffer, then
    // every new state from its sum
    if (layout_ == Layout::dense) {
        const std::size_t first_hidden = input_count_ + output_count_;
        const DenseStep s{states,         input_count_,          states + first_hidden, neuron_count_ - first_hidden,
                          matrix_.data(), scaled_biases_.data(), sums_.data(),          computed_states,
                          padded_};
        dense_step(s, avx2_);
    } else {
        sparse_sums();
        sigmoid_step(scaled_biases_.data(), sums_.data(), computed_states, padded_, avx2_);
    }

    for (std::size_t o = 0; o < output_count_; ++o) outputs[o] = computed_states[o];
}

}  // namespace stepstone::nn
