#include "nn/dnn_config.hpp"

#include <cmath>
#include <string>
#include <string_view>

#include "core/error.hpp"
#include "core/text.hpp"

namespace stepstone::nn {

namespace {

// `name` turns a field name into the key path of the message
template <class Name>
void check_config(const DnnConfig& c, Name name) {
    if (c.inputs < 1) throw ConfigError(concat(name("inputs"), " must be >= 1, got ", c.inputs));
    if (c.outputs < 1) throw ConfigError(concat(name("outputs"), " must be >= 1, got ", c.outputs));

    // ranges: finite and non-empty
    const auto check_range = [&](std::string_view lo_key, double lo, std::string_view hi_key, double hi) {
        if (!std::isfinite(lo)) throw ConfigError(concat(name(lo_key), " must be finite, got ", lo));
        if (!std::isfinite(hi)) throw ConfigError(concat(name(hi_key), " must be finite, got ", hi));
        if (!(lo < hi)) {
            throw ConfigError(concat(name(lo_key), " must be < ", name(hi_key), ", got ", lo, " and ", hi));
        }
    };
    check_range("weight_min", c.weight_min, "weight_max", c.weight_max);
    check_range("bias_min", c.bias_min, "bias_max", c.bias_max);
    if (!std::isfinite(c.bias_scale)) {
        throw ConfigError(concat(name("bias_scale"), " must be finite, got ", c.bias_scale));
    }
    if (!(c.polynomial_eta >= 0.0) || !std::isfinite(c.polynomial_eta)) {
        throw ConfigError(concat(name("polynomial_eta"), " must be >= 0, got ", c.polynomial_eta));
    }

    // probabilities
    const std::pair<std::string_view, double> rates[] = {
        {"parameter_mutation_rate", c.parameter_mutation_rate},
        {"rewire_connection_rate", c.rewire_connection_rate},
        {"add_connection_rate", c.add_connection_rate},
        {"delete_connection_rate", c.delete_connection_rate},
        {"add_neuron_rate", c.add_neuron_rate},
        {"delete_neuron_rate", c.delete_neuron_rate},
    };
    for (const auto& [key, rate] : rates) {
        if (!(rate >= 0.0 && rate <= 1.0)) throw ConfigError(concat(name(key), " must be in [0, 1], got ", rate));
    }
}

}  // namespace

void DnnConfig::validate() const {
    check_config(*this, [](std::string_view key) { return std::string(key); });
}

DnnConfig DnnConfig::from_json(JsonReader& reader) {
    constexpr double kHuge = 1e300;
    DnnConfig c;
    reader.read("inputs", c.inputs, 1, 1 << 20);
    reader.read("outputs", c.outputs, 1, 1 << 20);
    reader.read("weight_min", c.weight_min, -kHuge, kHuge);
    reader.read("weight_max", c.weight_max, -kHuge, kHuge);
    reader.read("bias_min", c.bias_min, -kHuge, kHuge);
    reader.read("bias_max", c.bias_max, -kHuge, kHuge);
    reader.read("bias_scale", c.bias_scale, -kHuge, kHuge);
    reader.read("parameter_mutation_rate", c.parameter_mutation_rate, 0.0, 1.0);
    reader.read("polynomial_eta", c.polynomial_eta, 0.0, kHuge);
    reader.read("rewire_connection_rate", c.rewire_connection_rate, 0.0, 1.0);
    reader.read("add_connection_rate", c.add_connection_rate, 0.0, 1.0);
    reader.read("delete_connection_rate", c.delete_connection_rate, 0.0, 1.0);
    reader.read("add_neuron_rate", c.add_neuron_rate, 0.0, 1.0);
    reader.read("delete_neuron_rate", c.delete_neuron_rate, 0.0, 1.0);
    reader.finish();
    check_config(c, [&](std::string_view key) { return reader.path_of(key); });
    return c;
}

}  // namespace stepstone::nn
