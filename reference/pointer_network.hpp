#pragma once

// A recurrent network evaluated the way sferes2/nn2 does it (docs/original.md: network,
// 8.4): neurons in a linked list, each with a linked list of incoming edges
// walked every step, the predecessors' outputs gathered into a buffer, a dot
// product with the weights and one exp per neuron, then a synchronous copy of
// every next state into the current one. Kept as the baseline of
// `stepstone bench nn` and `stepstone bench episode`.

#include <cstdint>
#include <list>
#include <vector>

namespace stepstone::reference {

/// A network as an edge list. Neurons are numbered inputs first, then
/// outputs, then hidden neurons (nn2's order).
struct NetworkSpec {
    /// One weighted connection source -> target (indices into the neurons).
    struct Edge {
        int source = 0;
        int target = 0;
        float weight = 0;
    };
    int inputs = 0;             ///< input neurons (their output is the input value)
    int outputs = 0;            ///< output neurons
    int hidden = 0;             ///< hidden neurons
    std::vector<float> biases;  ///< one per neuron (inputs' biases are unused), in [-5, 5]
    std::vector<Edge> edges;    ///< any directed graph: recurrence and self-loops allowed

    /// inputs + outputs + hidden.
    int neurons() const { return inputs + outputs + hidden; }
};

/// A random recurrent network: `connections` distinct edges, each from an
/// input or hidden neuron to an output or hidden neuron (nn2's valid sources
/// and targets), weights and biases uniform on [-5, 5]. Deterministic in
/// `seed`. Requires connections <= (inputs + hidden) * (outputs + hidden).
NetworkSpec random_network_spec(int inputs, int hidden, int outputs, int connections, std::uint64_t seed);

/// The nn2-style pointer network. Activation of a non-input neuron:
/// y = 1 / (1 + exp(5 b - sum w x)), from the previous step's outputs.
class PointerNetwork {
public:
    /// Builds the graph. Throws std::invalid_argument on an edge with an
    /// index out of range, into an input, or a bias count that is not
    /// spec.neurons().
    explicit PointerNetwork(const NetworkSpec& spec);
    /// Not copyable (edges point into the neuron list); movable, since a
    /// moved std::list keeps its nodes where they are.
    PointerNetwork(const PointerNetwork&) = delete;
    PointerNetwork& operator=(const PointerNetwork&) = delete;
    PointerNetwork(PointerNetwork&&) noexcept = default;
    PointerNetwork& operator=(PointerNetwork&&) noexcept = default;

    /// Sets every neuron state to 0 (nn2's init, at each start).
    void reset();
    /// One synchronous update: `in` holds `inputs` values, `out` receives
    /// `outputs` values in (0, 1).
    void step(const float* in, float* out);

private:
    struct Neuron;
    struct Edge {
        Neuron* source;
        float weight;
    };
    struct Neuron {
        float bias = 0;
        bool fixed = false;
        float current = 0;
        float next = 0;
        std::list<Edge> incoming;
        std::vector<float> gathered;
        std::vector<float> weights;
    };

    std::list<Neuron> neurons_;
    std::vector<Neuron*> inputs_;
    std::vector<Neuron*> outputs_;
};

}  // namespace stepstone::reference
