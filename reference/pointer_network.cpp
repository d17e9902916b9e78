#include "reference/pointer_network.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "core/rng.hpp"

namespace stepstone::reference {

NetworkSpec random_network_spec(int inputs, int hidden, int outputs, int connections, std::uint64_t seed) {
    NetworkSpec spec;
    spec.inputs = inputs;
    spec.outputs = outputs;
    spec.hidden = hidden;
    Rng rng(seed);
    for (int i = 0; i < spec.neurons(); ++i) spec.biases.push_back(static_cast<float>(rng.uniform(-5, 5)));

    // sources: inputs and hidden; targets: outputs and hidden
    std::vector<int> sources;
    std::vector<int> targets;
    for (int i = 0; i < inputs; ++i) sources.push_back(i);
    for (int i = 0; i < outputs; ++i) targets.push_back(inputs + i);
    for (int i = 0; i < hidden; ++i) {
        sources.push_back(inputs + outputs + i);
        targets.push_back(inputs + outputs + i);
    }
    const std::size_t pairs = sources.size() * targets.size();
    if (connections < 0 || static_cast<std::size_t>(connections) > pairs) {
        throw std::invalid_argument("random_network_spec: " + std::to_string(connections) +
                                    " connections do not fit in " + std::to_string(pairs) + " pairs");
    }

    // distinct pairs: the first `connections` of a shuffled list of all pairs
    std::vector<std::size_t> order(pairs);
    for (std::size_t k = 0; k < pairs; ++k) order[k] = k;
    rng.shuffle(std::span<std::size_t>(order));
    for (int c = 0; c < connections; ++c) {
        const std::size_t k = order[static_cast<std::size_t>(c)];
        spec.edges.push_back({sources[k / targets.size()], targets[k % targets.size()],
                              static_cast<float>(rng.uniform(-5, 5))});
    }
    return spec;
}

PointerNetwork::PointerNetwork(const NetworkSpec& spec) {
    const int n = spec.neurons();
    if (spec.inputs < 0 || spec.outputs < 0 || spec.hidden < 0 || static_cast<int>(spec.biases.size()) != n) {
        throw std::invalid_argument("PointerNetwork: expected " + std::to_string(n) + " biases, got " +
                                    std::to_string(spec.biases.size()));
    }
    std::vector<Neuron*> by_index;
    for (int i = 0; i < n; ++i) {
        Neuron& neuron = neurons_.emplace_back();
        neuron.bias = spec.biases[static_cast<std::size_t>(i)];
        neuron.fixed = i < spec.inputs;
        by_index.push_back(&neuron);
        if (i < spec.inputs) {
            inputs_.push_back(&neuron);
        } else if (i < spec.inputs + spec.outputs) {
            outputs_.push_back(&neuron);
        }
    }
    for (const auto& e : spec.edges) {
        if (e.source < 0 || e.source >= n || e.target < spec.inputs || e.target >= n) {
            throw std::invalid_argument("PointerNetwork: invalid edge " + std::to_string(e.source) + " -> " +
                                        std::to_string(e.target));
        }
        Neuron& target = *by_index[static_cast<std::size_t>(e.target)];
        target.incoming.push_back({by_index[static_cast<std::size_t>(e.source)], e.weight});
        target.weights.push_back(e.weight);
    }
    for (auto& neuron : neurons_) neuron.gathered.resize(neuron.incoming.size());
}

void PointerNetwork::reset() {
    for (auto& neuron : neurons_) {
        neuron.current = 0;
        neuron.next = 0;
    }
}

void PointerNetwork::step(const float* in, float* out) {
    // inputs: current and next are the input value
    for (std::size_t i = 0; i < inputs_.size(); ++i) {
        inputs_[i]->current = in[i];
        inputs_[i]->next = in[i];
    }

    // every other neuron from its predecessors' current outputs
    for (auto& neuron : neurons_) {
        if (neuron.fixed) continue;
        std::size_t k = 0;
        for (const auto& edge : neuron.incoming) neuron.gathered[k++] = edge.source->current;
        float sum = 0;
        for (std::size_t j = 0; j < neuron.gathered.size(); ++j)
            sum += neuron.weights[j] * neuron.gathered[j];
        neuron.next = 1.0f / (1.0f + std::exp(5.0f * neuron.bias - sum));
    }

    // synchronous update
    for (auto& neuron : neurons_) neuron.current = neuron.next;
    for (std::size_t i = 0; i < outputs_.size(); ++i) out[i] = outputs_[i]->current;
}

}  // namespace stepstone::reference
