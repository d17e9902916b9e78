#include "nn/network_lanes.hpp"

#include <algorithm>
#include <cstring>
#include <string>
#include <utility>

#include "core/assert.hpp"
#include "core/cpu.hpp"
#include "core/error.hpp"
#include "nn/activation.hpp"

namespace stepstone::nn {

namespace {

// One value per network of the batch (GCC/Clang vector extension, plain
// lane-wise IEEE arithmetic): an AVX register, or two SSE ones in the
// baseline build.
typedef float Lanes __attribute__((vector_size(NetworkLanes::kLanes * sizeof(float))));
constexpr std::size_t kLanes = NetworkLanes::kLanes;
// Two columns' lanes: an AVX-512 register.
typedef float PairLanes __attribute__((vector_size(2 * NetworkLanes::kLanes * sizeof(float))));

// Columns summed in one pass over the rows: their accumulators, the row's
// states and a product fill the 16 AVX registers, or (the AVX-512 build, 32
// registers) every column of a 12-15-3 network.
constexpr std::size_t kBlockColumns = 12;
constexpr std::size_t kWideBlockColumns = 18;

struct LaneStep {
    const float* weights;        // rows x columns x kLanes
    const float* scaled_biases;  // columns x kLanes
    float* states;               // rows x kLanes
    float* computed;             // columns x kLanes
    std::size_t rows;
    std::size_t columns;
    std::size_t input_count;
    std::size_t output_count;
};

[[gnu::always_inline]] inline void load(Lanes& v, const float* p) { std::memcpy(&v, p, sizeof v); }

[[gnu::always_inline]] inline void store(float* p, const Lanes& v) { std::memcpy(p, &v, sizeof v); }

// Sums of `Columns` columns from `first`: for each row in ascending order,
// acc[c] += x_row * w[row][c], every lane on its own network.
template <std::size_t Columns>
[[gnu::always_inline]] inline void column_block(const LaneStep& s, std::size_t first) {
    Lanes acc[Columns] = {};
    const float* w = s.weights + first * kLanes;
    for (std::size_t r = 0; r < s.rows; ++r, w += s.columns * kLanes) {
        Lanes x;
        load(x, s.states + r * kLanes);
#pragma GCC unroll 18
        for (std::size_t c = 0; c < Columns; ++c) {
            Lanes weights;
            load(weights, w + c * kLanes);
            acc[c] += x * weights;
        }
    }
#pragma GCC unroll 18
    for (std::size_t c = 0; c < Columns; ++c) store(s.computed + (first + c) * kLanes, acc[c]);
}

template <std::size_t... Sizes>
[[gnu::always_inline]] inline void column_tail(const LaneStep& s, std::size_t first, std::size_t count,
                                               std::index_sequence<Sizes...>) {
    // the block of the remaining `count` columns, 1 <= count <= sizeof...(Sizes)
    ((count == Sizes + 1 ? column_block<Sizes + 1>(s, first) : void()), ...);
}

// Sigmoids of the columns from `first`, `Wide` holding one or two columns' lanes.
// A sigmoid is a long chain of dependent operations (the exponential's
// polynomial, a division); with two columns a vector the same chains take half
// the instructions, so twice as many are in flight at once.
template <class Wide>
[[gnu::always_inline]] inline std::size_t sigmoid_columns(const LaneStep& s, std::size_t first) {
    constexpr std::size_t kColumns = sizeof(Wide) / sizeof(Lanes);
    std::size_t c = first;
    for (; c + kColumns <= s.columns; c += kColumns) {
        Wide bias;
        Wide sum;
        std::memcpy(&bias, s.scaled_biases + c * kLanes, sizeof bias);
        std::memcpy(&sum, s.computed + c * kLanes, sizeof sum);
        sigmoid_lanes(bias, sum);
        std::memcpy(s.computed + c * kLanes, &sum, sizeof sum);
    }
    return c;
}

template <std::size_t Block, class Wide>
[[gnu::always_inline]] inline void lane_step(const LaneStep& s) {
    std::size_t first = 0;
    for (; first + Block <= s.columns; first += Block) column_block<Block>(s, first);
    if (first < s.columns) column_tail(s, first, s.columns - first, std::make_index_sequence<Block - 1>{});
    // every sum's sigmoid, once the sums are out of registers
    sigmoid_columns<Lanes>(s, sigmoid_columns<Wide>(s, 0));
    // the new hidden states become the next step's rows (every sum above read the old ones)
    // (a vector a column, inline: a call of memcpy cost more than the copy)
    float* to = s.states + s.input_count * kLanes;
    for (std::size_t c = s.output_count; c < s.columns; ++c, to += kLanes) {
        Lanes state;
        load(state, s.computed + c * kLanes);
        store(to, state);
    }
}

// built twice from the same source, as Network's kernels are: both compute the same bits
void lane_step_baseline(const LaneStep& s) { lane_step<kBlockColumns, Lanes>(s); }

#if defined(__x86_64__) || defined(__i386__)
[[gnu::target("avx2")]] void lane_step_avx2(const LaneStep& s) { lane_step<kBlockColumns, Lanes>(s); }

[[gnu::target("avx2,avx512f,avx512vl,avx512dq")]] void lane_step_avx512(const LaneStep& s) {
    lane_step<kWideBlockColumns, PairLanes>(s);
}
#endif

}  // namespace

namespace {

std::size_t hidden_count(const Genome& genome) {
    return genome.neuron_count() - genome.input_count() - genome.output_count();
}

std::size_t largest_hidden(std::span<const Genome* const> genomes) {
    if (genomes.empty() || genomes.size() > NetworkLanes::kLanes) {
        throw DataError("a batch of networks holds 1 to 8 genomes, not " + std::to_string(genomes.size()));
    }
    std::size_t hidden = 0;
    for (const Genome* genome : genomes) hidden = std::max(hidden, hidden_count(*genome));
    return hidden;
}

}  // namespace

NetworkLanes::NetworkLanes(std::size_t inputs, std::size_t outputs, std::size_t max_hidden,
                           const DnnConfig& config, Network::Simd simd)
    : config_(config),
      lanes_(kLanes),
      input_count_(inputs),
      output_count_(outputs),
      rows_(inputs + max_hidden),
      columns_(outputs + max_hidden),
      avx2_(simd != Network::Simd::baseline && cpu_has_avx2()),
      avx512_(simd == Network::Simd::automatic && avx512_kernels_allowed()) {
    weights_.assign(rows_ * columns_ * kLanes, 0.0f);
    scaled_biases_.assign(columns_ * kLanes, 0.0f);
    states_.assign(rows_ * kLanes, 0.0f);
    computed_.assign(columns_ * kLanes, 0.0f);
}

NetworkLanes::NetworkLanes(std::span<const Genome* const> genomes, const DnnConfig& config,
                           Network::Simd simd)
    : NetworkLanes(genomes.empty() ? 0 : genomes[0]->input_count(),
                   genomes.empty() ? 0 : genomes[0]->output_count(), largest_hidden(genomes), config, simd) {
    lanes_ = genomes.size();
    for (std::size_t lane = 0; lane < lanes_; ++lane) load(lane, *genomes[lane]);
}

void NetworkLanes::load(std::size_t lane, const Genome& genome) {
    STEPSTONE_ASSERT(lane < lanes_);
    if (genome.input_count() != input_count_ || genome.output_count() != output_count_) {
        throw DataError("the networks of a batch must have the same input and output counts");
    }
    if (hidden_count(genome) > max_hidden()) {
        throw DataError("a network of " + std::to_string(hidden_count(genome)) +
                        " hidden neurons does not fit lanes made for " + std::to_string(max_hidden()));
    }
    for (std::size_t cell = 0; cell < rows_ * columns_; ++cell) weights_[cell * kLanes + lane] = 0.0f;
    for (std::size_t column = 0; column < columns_; ++column) scaled_biases_[column * kLanes + lane] = 0.0f;
    // neurons: inputs, outputs, hidden; a column is a neuron after the inputs
    for (std::size_t k = input_count_; k < genome.neuron_count(); ++k) {
        scaled_biases_[(k - input_count_) * kLanes + lane] =
            developed_scaled_bias(genome.biases()[k], config_);
    }
    for (const auto& c : genome.connections()) {
        STEPSTONE_ASSERT(genome.can_be_source(c.source));
        const std::size_t row = c.source < input_count_ ? c.source : c.source - output_count_;
        const std::size_t column = c.target - input_count_;
        weights_[(row * columns_ + column) * kLanes + lane] = developed_weight(c.weight, config_);
    }
    reset(lane);
}

void NetworkLanes::reset() { std::fill(states_.begin(), states_.end(), 0.0f); }

void NetworkLanes::reset(std::size_t lane) {
    STEPSTONE_ASSERT(lane < lanes_);
    for (std::size_t r = 0; r < rows_; ++r) states_[r * kLanes + lane] = 0.0f;
}

void NetworkLanes::step() {
    const LaneStep s{weights_.data(), scaled_biases_.data(), states_.data(), computed_.data(), rows_,
                     columns_,        input_count_,          output_count_};
#if defined(__x86_64__) || defined(__i386__)
    if (avx512_) return lane_step_avx512(s);
    if (avx2_) return lane_step_avx2(s);
#endif
    lane_step_baseline(s);
}

}  // namespace stepstone::nn
