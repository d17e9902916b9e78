#pragma once

#include <cstddef>
#include <list>

#include "nn/dnn_config.hpp"
#include "nn/genome.hpp"

namespace stepstone::reference {

/// The tests' oracle of nn::Network and nn::NetworkLanes: a plain evaluation of the genome graph in nn2's
/// manner (docs/original.md: network, 8.4): one heap node per neuron in a linked list, each holding a linked
/// list of incoming edges that point to their source node, walked every step.
///
/// Each neuron sums its incoming edges in float, from 0, in ascending source
/// index (not in the genome's connection order): the order that both layouts
/// of Network compute. With `exact_exp` false it uses the same float sigmoid
/// as Network and must equal it bit for bit (the tests' oracle). With `exact_exp` true it computes
/// the sigmoid with std::exp in double, as nn2 does (the tests compare Network with it to a
/// tolerance; `stepstone bench` times Network against pointer_network.hpp's).
class ReferenceNetwork {
public:
    ReferenceNetwork(const nn::Genome& genome, const nn::DnnConfig& config, bool exact_exp = false);
    ReferenceNetwork(const ReferenceNetwork&) = delete;
    ReferenceNetwork& operator=(const ReferenceNetwork&) = delete;

    /// Sets every neuron state to 0.
    void reset();
    /// One synchronous update, same contract as Network::step.
    void step(const float* inputs, float* outputs);

private:
    struct Node;
    struct Edge {
        const Node* source;
        float weight;
    };
    struct Node {
        nn::NeuronKind kind;
        float scaled_bias;
        float state = 0.0f;
        float next = 0.0f;
        std::list<Edge> in_edges;
    };

    std::list<Node> nodes_;
    bool exact_exp_;
};

}  // namespace stepstone::reference
