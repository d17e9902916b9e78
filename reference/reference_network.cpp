#include "reference/reference_network.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "nn/activation.hpp"

namespace stepstone::reference {

using namespace stepstone::nn;

namespace {

// the sigmoid through std::exp in double, as nn2 computes it
double sigmoid_exact(double scaled_bias, double sum) { return 1.0 / (1.0 + std::exp(scaled_bias - sum)); }

}  // namespace

ReferenceNetwork::ReferenceNetwork(const Genome& genome, const DnnConfig& config, bool exact_exp)
    : exact_exp_(exact_exp) {
    // one list node per neuron; a table of their addresses to link the edges
    std::vector<Node*> by_index;
    for (std::size_t n = 0; n < genome.neuron_count(); ++n) {
        nodes_.push_back(
            Node{genome.kind(n), developed_scaled_bias(genome.biases()[n], config), 0.0f, 0.0f, {}});
        by_index.push_back(&nodes_.back());
    }
    // each neuron's incoming edges in ascending source order: the summation
    // order that Network's layouts share
    std::vector<Connection> edges = genome.connections();
    std::sort(edges.begin(), edges.end(),
              [](const Connection& a, const Connection& b) { return a.source < b.source; });
    for (const auto& c : edges) {
        by_index[c.target]->in_edges.push_back(Edge{by_index[c.source], developed_weight(c.weight, config)});
    }
}

void ReferenceNetwork::reset() {
    for (auto& node : nodes_) node.state = node.next = 0.0f;
}

void ReferenceNetwork::step(const float* inputs, float* outputs) {
    // inputs are fixed: their state is the sensor value
    const float* input = inputs;
    for (auto& node : nodes_) {
        if (node.kind == NeuronKind::input) node.state = node.next = *input++;
    }

    // every other neuron reads the current states of its predecessors
    for (auto& node : nodes_) {
        if (node.kind == NeuronKind::input) continue;
        float sum = 0.0f;
        for (const auto& edge : node.in_edges) sum += edge.weight * edge.source->state;
        node.next = exact_exp_ ? static_cast<float>(sigmoid_exact(node.scaled_bias, sum))
                               : sigmoid(node.scaled_bias, sum);
    }

    // then all switch at once, and the outputs are read
    float* output = outputs;
    for (auto& node : nodes_) {
        node.state = node.next;
        if (node.kind == NeuronKind::output) *output++ = node.state;
    }
}

}  // namespace stepstone::reference
