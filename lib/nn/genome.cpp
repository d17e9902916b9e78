#include "nn/genome.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/assert.hpp"
#include "core/error.hpp"
#include "core/text.hpp"

namespace stepstone::nn {

namespace {

constexpr std::size_t kMaxNeurons = 1u << 24;

std::size_t read_count(const nlohmann::json& json, const char* key) {
    const auto it = json.find(key);
    if (it == json.end()) throw DataError(concat("genome: missing key \"", key, '"'));
    if (!it->is_number_unsigned() || it->get<std::uint64_t>() == 0 || it->get<std::uint64_t>() > kMaxNeurons) {
        throw DataError(concat("genome: ", key, " must be a positive integer, got ", describe(*it)));
    }
    return it->get<std::size_t>();
}

double read_gene(const nlohmann::json& value, const std::string& where) {
    if (!value.is_number()) throw DataError(concat("genome: ", where, " must be a number, got ", describe(value)));
    const double gene = value.get<double>();
    if (!(gene >= 0.0 && gene <= 1.0)) {
        throw DataError(concat("genome: ", where, " must be in [0, 1], got ", describe(value)));
    }
    return gene;
}

std::uint32_t read_index(const nlohmann::json& value, std::size_t neurons, const std::string& where) {
    if (!value.is_number_unsigned() || value.get<std::uint64_t>() >= neurons) {
        throw DataError(concat("genome: ", where, " must be a neuron index below ", neurons, ", got ",
                               describe(value)));
    }
    return static_cast<std::uint32_t>(value.get<std::uint64_t>());
}

}  // namespace

Genome::Genome(std::size_t input_count, std::size_t output_count)
    : input_count_(input_count), output_count_(output_count), biases_(input_count + output_count, 0.5) {
    STEPSTONE_ASSERT(input_count > 0 && output_count > 0);
}

Genome Genome::random_perceptron(std::size_t input_count, std::size_t output_count, Rng& rng) {
    Genome genome(input_count, output_count);
    // weights first (input-major), then biases: uniform genes as nn2's random()
    for (std::size_t i = 0; i < input_count; ++i) {
        for (std::size_t o = 0; o < output_count; ++o) {
            genome.connections_.push_back(Connection{static_cast<std::uint32_t>(i),
                                                     static_cast<std::uint32_t>(input_count + o), rng.uniform()});
        }
    }
    for (auto& bias : genome.biases_) bias = rng.uniform();
    return genome;
}

Genome Genome::random_perceptron(const DnnConfig& config, Rng& rng) {
    return random_perceptron(static_cast<std::size_t>(config.inputs), static_cast<std::size_t>(config.outputs), rng);
}

NeuronKind Genome::kind(std::size_t neuron) const {
    STEPSTONE_ASSERT(neuron < biases_.size());
    if (neuron < input_count_) return NeuronKind::input;
    if (neuron < input_count_ + output_count_) return NeuronKind::output;
    return NeuronKind::hidden;
}

bool Genome::has_connection(std::size_t source, std::size_t target) const {
    return std::any_of(connections_.begin(), connections_.end(),
                       [&](const Connection& c) { return c.source == source && c.target == target; });
}

std::size_t Genome::add_hidden(double bias) {
    biases_.push_back(bias);
    return biases_.size() - 1;
}

void Genome::add_connection(std::size_t source, std::size_t target, double weight) {
    STEPSTONE_ASSERT(source < neuron_count() && target < neuron_count());
    STEPSTONE_ASSERT(can_be_source(source) && can_be_target(target));
    STEPSTONE_ASSERT(!has_connection(source, target));
    connections_.push_back(
        Connection{static_cast<std::uint32_t>(source), static_cast<std::uint32_t>(target), weight});
}

void Genome::remove_connection(std::size_t index) {
    STEPSTONE_ASSERT(index < connections_.size());
    connections_.erase(connections_.begin() + static_cast<std::ptrdiff_t>(index));
}

void Genome::remove_hidden(std::size_t neuron) {
    STEPSTONE_ASSERT(kind(neuron) == NeuronKind::hidden);
    std::erase_if(connections_, [&](const Connection& c) { return c.source == neuron || c.target == neuron; });
    // later neurons move down by one
    for (auto& c : connections_) {
        if (c.source > neuron) --c.source;
        if (c.target > neuron) --c.target;
    }
    biases_.erase(biases_.begin() + static_cast<std::ptrdiff_t>(neuron));
}

std::size_t Genome::simplify() {
    // backward reachability from the outputs along the edges
    std::vector<char> useful(neuron_count(), 0);
    std::vector<std::size_t> stack;
    for (std::size_t o = input_count_; o < input_count_ + output_count_; ++o) {
        useful[o] = 1;
        stack.push_back(o);
    }
    while (!stack.empty()) {
        const std::size_t n = stack.back();
        stack.pop_back();
        for (const auto& c : connections_) {
            if (c.target == n && !useful[c.source]) {
                useful[c.source] = 1;
                stack.push_back(c.source);
            }
        }
    }

    // remove useless hidden neurons from the last, so indices stay valid
    std::size_t removed = 0;
    for (std::size_t n = neuron_count(); n-- > input_count_ + output_count_;) {
        if (!useful[n]) {
            remove_hidden(n);
            ++removed;
        }
    }
    return removed;
}

nlohmann::json Genome::to_json() const {
    nlohmann::json connections = nlohmann::json::array();
    for (const auto& c : connections_) connections.push_back({c.source, c.target, c.weight});
    return {{"inputs", input_count_},
            {"outputs", output_count_},
            {"biases", biases_},
            {"connections", std::move(connections)}};
}

Genome Genome::from_json(const nlohmann::json& json) {
    if (!json.is_object()) throw DataError(concat("genome must be a JSON object, got ", describe(json)));
    for (const auto& [key, value] : json.items()) {
        if (key != "inputs" && key != "outputs" && key != "biases" && key != "connections") {
            throw DataError(concat("genome: unknown key \"", key, '"'));
        }
    }
    Genome genome(read_count(json, "inputs"), read_count(json, "outputs"));

    // one bias gene per neuron, at least the inputs and outputs
    const auto biases = json.find("biases");
    if (biases == json.end()) throw DataError("genome: missing key \"biases\"");
    if (!biases->is_array() || biases->size() < genome.neuron_count() || biases->size() > kMaxNeurons) {
        throw DataError(concat("genome: biases must be an array of at least ", genome.neuron_count(),
                               " genes, got ", describe(*biases)));
    }
    genome.biases_.clear();
    for (std::size_t n = 0; n < biases->size(); ++n) {
        genome.biases_.push_back(read_gene((*biases)[n], concat("biases[", n, ']')));
    }

    // connections as [source, target, weight] with the graph's invariants
    const auto connections = json.find("connections");
    if (connections == json.end()) throw DataError("genome: missing key \"connections\"");
    if (!connections->is_array()) {
        throw DataError(concat("genome: connections must be an array, got ", describe(*connections)));
    }
    for (std::size_t k = 0; k < connections->size(); ++k) {
        const auto& item = (*connections)[k];
        const std::string where = concat("connections[", k, ']');
        if (!item.is_array() || item.size() != 3) {
            throw DataError(concat("genome: ", where, " must be [source, target, weight], got ", describe(item)));
        }
        const auto source = read_index(item[0], genome.neuron_count(), where + " source");
        const auto target = read_index(item[1], genome.neuron_count(), where + " target");
        const double weight = read_gene(item[2], where + " weight");
        if (!genome.can_be_source(source)) {
            throw DataError(concat("genome: ", where, " starts at output neuron ", source));
        }
        if (!genome.can_be_target(target)) {
            throw DataError(concat("genome: ", where, " ends at input neuron ", target));
        }
        if (genome.has_connection(source, target)) {
            throw DataError(concat("genome: ", where, " duplicates the edge ", source, " -> ", target));
        }
        genome.connections_.push_back(Connection{source, target, weight});
    }
    return genome;
}

}  // namespace stepstone::nn
