#include "nn/mutation.hpp"

#include <algorithm>
#include <cmath>

#include "core/assert.hpp"

namespace stepstone::nn {

namespace {

// valid sources are the inputs and the hidden neurons: draw among them uniformly
std::size_t random_source(const Genome& genome, Rng& rng) {
    const std::size_t choices = genome.input_count() + genome.hidden_count();
    const auto k = static_cast<std::size_t>(rng.below(choices));
    return k < genome.input_count() ? k : k + genome.output_count();
}

// valid targets are the outputs and the hidden neurons, a contiguous range
std::size_t random_target(const Genome& genome, Rng& rng) {
    const std::size_t choices = genome.output_count() + genome.hidden_count();
    return genome.input_count() + static_cast<std::size_t>(rng.below(choices));
}

std::size_t attempts(const Genome& genome) { return genome.neuron_count() * genome.neuron_count(); }

}  // namespace

double polynomial_mutation(double gene, double eta, Rng& rng, Math math) {
    const double r = rng.uniform();
    const double exponent = 1.0 / (eta + 1.0);
    const auto power = [&](double base) {
        return math == Math::portable ? portable::pow(base, exponent) : std::pow(base, exponent);
    };
    const double delta = r < 0.5 ? power(2.0 * r) - 1.0 : 1.0 - power(2.0 * (1.0 - r));
    return std::clamp(gene + delta, 0.0, 1.0);
}

std::size_t mutate_weights(Genome& genome, const DnnConfig& config, Rng& rng) {
    std::size_t mutated = 0;
    for (std::size_t k = 0; k < genome.connection_count(); ++k) {
        if (rng.bernoulli(config.parameter_mutation_rate)) {
            auto& weight = genome.connection(k).weight;
            weight = polynomial_mutation(weight, config.polynomial_eta, rng, config.math);
            ++mutated;
        }
    }
    return mutated;
}

bool rewire_one_connection(Genome& genome, const DnnConfig& config, Rng& rng) {
    for (std::size_t k = 0; k < genome.connection_count(); ++k) {
        if (!rng.bernoulli(config.rewire_connection_rate)) continue;

        // the edge is taken out while a new endpoint is drawn, so the old one may come back
        const Connection old = genome.connections()[k];
        const bool redraw_source = rng.bernoulli(0.5);
        const std::size_t max_attempts = attempts(genome);
        for (std::size_t attempt = 0; attempt < max_attempts; ++attempt) {
            const std::size_t source = redraw_source ? random_source(genome, rng) : old.source;
            const std::size_t target = redraw_source ? old.target : random_target(genome, rng);
            const bool is_old = source == old.source && target == old.target;
            if (is_old || !genome.has_connection(source, target)) {
                auto& edge = genome.connection(k);
                edge.source = static_cast<std::uint32_t>(source);
                edge.target = static_cast<std::uint32_t>(target);
                break;
            }
        }
        return true;
    }
    return false;
}

std::size_t mutate_biases(Genome& genome, const DnnConfig& config, Rng& rng) {
    std::size_t mutated = 0;
    for (auto& bias : genome.biases()) {
        if (rng.bernoulli(config.parameter_mutation_rate)) {
            bias = polynomial_mutation(bias, config.polynomial_eta, rng, config.math);
            ++mutated;
        }
    }
    return mutated;
}

bool add_random_connection(Genome& genome, Rng& rng) {
    const std::size_t max_attempts = attempts(genome);
    for (std::size_t attempt = 0; attempt < max_attempts; ++attempt) {
        const std::size_t source = random_source(genome, rng);
        const std::size_t target = random_target(genome, rng);
        if (!genome.has_connection(source, target)) {
            genome.add_connection(source, target, rng.uniform());
            return true;
        }
    }
    return false;
}

bool delete_random_connection(Genome& genome, Rng& rng) {
    if (genome.connection_count() == 0) return false;
    genome.remove_connection(static_cast<std::size_t>(rng.below(genome.connection_count())));
    return true;
}

bool add_neuron_on_connection(Genome& genome, Rng& rng) {
    if (genome.connection_count() == 0) return false;
    const auto k = static_cast<std::size_t>(rng.below(genome.connection_count()));
    const Connection old = genome.connections()[k];
    genome.remove_connection(k);
    const std::size_t neuron = genome.add_hidden(rng.uniform());
    genome.add_connection(old.source, neuron, old.weight);
    genome.add_connection(neuron, old.target, old.weight);
    return true;
}

bool delete_random_neuron(Genome& genome, Rng& rng) {
    if (genome.hidden_count() == 0) return false;
    const std::size_t first_hidden = genome.input_count() + genome.output_count();
    genome.remove_hidden(first_hidden + static_cast<std::size_t>(rng.below(genome.hidden_count())));
    return true;
}

MutationReport mutate(Genome& genome, const DnnConfig& config, Rng& rng) {
    STEPSTONE_ASSERT(genome.input_count() == static_cast<std::size_t>(config.inputs));
    STEPSTONE_ASSERT(genome.output_count() == static_cast<std::size_t>(config.outputs));
    MutationReport report;

    // nn2 _change_conns, then _change_neurons
    report.weights_mutated = mutate_weights(genome, config, rng);
    report.rewired_connection = rewire_one_connection(genome, config, rng);
    report.biases_mutated = mutate_biases(genome, config, rng);

    // structural operators, each behind its own coin
    if (rng.bernoulli(config.add_connection_rate)) report.added_connection = add_random_connection(genome, rng);
    if (rng.bernoulli(config.delete_connection_rate)) {
        report.deleted_connection = delete_random_connection(genome, rng);
    }
    if (rng.bernoulli(config.add_neuron_rate)) report.added_neuron = add_neuron_on_connection(genome, rng);
    if (rng.bernoulli(config.delete_neuron_rate)) report.deleted_neuron = delete_random_neuron(genome, rng);
    return report;
}

}  // namespace stepstone::nn
