// `nn`: network steps of nn::Network against the nn2-style pointer network.

#include <memory>
#include <vector>

#include "bench/cases.hpp"
#include "bench/spec_genome.hpp"
#include "core/rng.hpp"
#include "nn/network.hpp"
#include "reference/pointer_network.hpp"

namespace stepstone::bench {

using namespace stepstone::reference;  // the baselines

namespace {

constexpr int kInputs = 12;
constexpr int kHidden = 15;
constexpr int kOutputs = 3;
constexpr int kConnections = 120;
// distinct input vectors cycled through, so inputs change every step
constexpr int kInputSets = 256;

// both networks step over the same inputs; the outputs are summed so the
// work cannot be optimised away
template <class Network>
struct Stepper {
    Network network;
    std::shared_ptr<const std::vector<float>> inputs;
    int steps = 0;
    float checksum = 0;

    std::uint64_t run() {
        float out[kOutputs];
        network.reset();
        for (int s = 0; s < steps; ++s) {
            const float* in = inputs->data() + static_cast<std::size_t>(s % kInputSets) * kInputs;
            network.step(in, out);
            checksum += out[0];
        }
        return static_cast<std::uint64_t>(steps);
    }
};

Workload make_nn_workload(Size size) {
    const NetworkSpec spec = random_network_spec(kInputs, kHidden, kOutputs, kConnections, 2013);
    auto inputs = std::make_shared<std::vector<float>>(static_cast<std::size_t>(kInputSets) * kInputs);
    Rng rng(12);
    // sensor-like inputs: laser levels in [0, 1], binary lights and bumpers
    for (std::size_t k = 0; k < inputs->size(); ++k) {
        const auto channel = k % kInputs;
        (*inputs)[k] = channel < 3 ? static_cast<float>(rng.uniform()) : (rng.bernoulli(0.2) ? 1.0f : 0.0f);
    }
    const int steps = size == Size::full ? 100000 : 20000;

    auto baseline = std::make_shared<Stepper<PointerNetwork>>(
        Stepper<PointerNetwork>{PointerNetwork(spec), inputs, steps});
    auto candidate = std::make_shared<Stepper<nn::Network>>(
        Stepper<nn::Network>{nn::Network(genome_from_spec(spec), nn::DnnConfig{}), inputs, steps});
    check_same_network(baseline->network, candidate->network, kInputs, kOutputs);
    return Workload{[baseline] { return baseline->run(); }, [candidate] { return candidate->run(); }};
}

}  // namespace

void add_nn_cases(Registry& registry) {
    registry.add(
        Case{"nn", "steps",
             "a random 12-15-3 recurrent network of 120 connections: nn::Network vs nn2-style pointer graph",
             2.5, make_nn_workload});
}

}  // namespace stepstone::bench
