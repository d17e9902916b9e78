#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/rng.hpp"
#include "nn/dnn_config.hpp"

namespace stepstone::nn {

/// Role of a neuron. Inputs are fixed to the sensor values; outputs are read
/// as effectors and never feed another neuron (nn2 _random_src/_random_tgt).
enum class NeuronKind : std::uint8_t { input, output, hidden };

/// A directed weighted edge between two neurons of a Genome.
struct Connection {
    /// Index of the source neuron: an input or a hidden neuron.
    std::uint32_t source = 0;
    /// Index of the target neuron: an output or a hidden neuron.
    std::uint32_t target = 0;
    /// Weight gene in [0, 1] (developed with DnnConfig::weight_min/max).
    double weight = 0.5;

    friend bool operator==(const Connection&, const Connection&) = default;
};

/// The direct encoding of nn2's DNN (docs/original.md: network): a directed graph
/// where recurrence and self-loops are allowed, with one bias gene per neuron
/// and one weight gene per connection, every gene in [0, 1].
///
/// Neurons are numbered inputs first, then outputs, then hidden neurons;
/// removing a hidden neuron renumbers the later ones. Connections keep their
/// insertion order, which fixes the order of random edge picks in mutation;
/// networks sum a neuron's inputs in ascending source order whatever the
/// connection order. Invariants: no connection into an input, none out of an
/// output, at most one connection per ordered pair. Editing methods check
/// them with STEPSTONE_ASSERT; from_json checks them with exceptions.
class Genome {
public:
    /// A genome with the given neurons, no hidden neuron, no connection, all bias genes 0.5.
    Genome(std::size_t input_count, std::size_t output_count);

    /// The initial genome of collectball (nn2 `init = ff`, docs/original.md: network):
    /// every input connected to every output, each weight and bias gene drawn
    /// uniformly on [0, 1]. Connections are ordered by input, then output.
    static Genome random_perceptron(std::size_t input_count, std::size_t output_count, Rng& rng);
    /// random_perceptron with the counts of `config`.
    static Genome random_perceptron(const DnnConfig& config, Rng& rng);

    std::size_t input_count() const { return input_count_; }
    std::size_t output_count() const { return output_count_; }
    std::size_t hidden_count() const { return biases_.size() - input_count_ - output_count_; }
    std::size_t neuron_count() const { return biases_.size(); }
    std::size_t connection_count() const { return connections_.size(); }

    /// Kind of neuron `neuron` (< neuron_count()).
    NeuronKind kind(std::size_t neuron) const;
    /// True for inputs and hidden neurons, the valid connection sources.
    bool can_be_source(std::size_t neuron) const { return kind(neuron) != NeuronKind::output; }
    /// True for outputs and hidden neurons, the valid connection targets.
    bool can_be_target(std::size_t neuron) const { return neuron >= input_count_; }
    /// Whether a connection source -> target exists (linear scan).
    bool has_connection(std::size_t source, std::size_t target) const;

    /// Bias genes, one per neuron (inputs included: nn2 mutates them too, they are unused).
    const std::vector<double>& biases() const { return biases_; }
    std::vector<double>& biases() { return biases_; }
    /// Connections in their order of insertion.
    const std::vector<Connection>& connections() const { return connections_; }
    /// Mutable access to weight genes; use the methods below to change the topology.
    Connection& connection(std::size_t index) { return connections_[index]; }

    /// Adds a hidden neuron with bias gene `bias`; returns its index.
    std::size_t add_hidden(double bias);
    /// Appends source -> target. The edge must be valid and not yet present.
    void add_connection(std::size_t source, std::size_t target, double weight);
    /// Removes connection `index`, keeping the order of the others.
    void remove_connection(std::size_t index);
    /// Removes hidden neuron `neuron` and every connection touching it.
    void remove_hidden(std::size_t neuron);

    /// nn2's simplify (docs/original.md: network): removes every hidden neuron with no
    /// directed path to an output. Neurons unreachable from the inputs stay.
    /// Returns the number of neurons removed.
    std::size_t simplify();

    /// Compact JSON: {"inputs":I,"outputs":O,"biases":[...],"connections":[[s,t,w],...]}.
    /// Doubles are written so that from_json restores them exactly.
    nlohmann::json to_json() const;
    /// Inverse of to_json. Throws DataError with a one-line message on a
    /// missing or extra key, a wrong type, a gene outside [0, 1] or NaN, an
    /// index out of range, an edge into an input or out of an output, or a
    /// duplicate edge.
    static Genome from_json(const nlohmann::json& json);

    friend bool operator==(const Genome&, const Genome&) = default;

private:
    std::size_t input_count_;
    std::size_t output_count_;
    std::vector<double> biases_;
    std::vector<Connection> connections_;
};

/// Developed value of a gene: gene * (hi - lo) + lo (sferes2 phen::Parameters).
inline double develop(double gene, double lo, double hi) { return gene * (hi - lo) + lo; }

/// Float weight of a connection gene, as every network rounds it.
inline float developed_weight(double gene, const DnnConfig& config) {
    return static_cast<float>(develop(gene, config.weight_min, config.weight_max));
}

/// Float bias_scale * developed bias, as every network rounds it.
inline float developed_scaled_bias(double gene, const DnnConfig& config) {
    return static_cast<float>(config.bias_scale * develop(gene, config.bias_min, config.bias_max));
}

}  // namespace stepstone::nn
