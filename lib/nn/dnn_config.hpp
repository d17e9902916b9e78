#pragma once

#include "core/config.hpp"
#include "core/portable_math.hpp"

namespace stepstone::nn {

/// Parameters of the DNN genome, its development and its mutation. The
/// defaults are those of collectball + nn2 (docs/original.md: network): a 12 -> 3
/// perceptron, weights and biases in [-5, 5], bias scaled by 5 in the
/// sigmoid, polynomial mutation (eta 15) at rate 0.1 per weight and bias, and
/// the structural rates 0.03 / 0.15 / 0.05 / 0.05 / 0.05.
struct DnnConfig {
    /// Number of input neurons (sensors).
    int inputs = 12;
    /// Number of output neurons (effectors).
    int outputs = 3;
    /// A weight gene g in [0, 1] develops to g * (weight_max - weight_min) + weight_min.
    double weight_min = -5.0;
    double weight_max = 5.0;
    /// A bias gene develops the same way onto [bias_min, bias_max].
    double bias_min = -5.0;
    double bias_max = 5.0;
    /// lambda of nn2's AfSigmoidBias: y = 1 / (1 + exp(bias_scale * b - sum w x)).
    double bias_scale = 5.0;
    /// Probability that one weight or bias gene mutates (sferes2 evo_float::mutation_rate).
    double parameter_mutation_rate = 0.1;
    /// eta of the polynomial mutation of a gene (sferes2 evo_float::eta_m).
    double polynomial_eta = 15.0;
    /// Per-edge probability of rewiring it; at most one edge is rewired per mutation.
    double rewire_connection_rate = 0.03;
    /// Probability of adding one connection between a random source and target.
    double add_connection_rate = 0.15;
    /// Probability of deleting one random connection.
    double delete_connection_rate = 0.05;
    /// Probability of splitting one random connection with a new hidden neuron.
    double add_neuron_rate = 0.05;
    /// Probability of deleting one random hidden neuron with its connections.
    double delete_neuron_rate = 0.05;
    /// The power of the polynomial mutation (set from a run config's "math"):
    /// stepstone's own by default, as the task's.
    Math math = Math::portable;

    /// Throws ConfigError (one line naming the field) unless every count is
    /// >= 1, every rate in [0, 1], eta >= 0, min < max and all values finite.
    void validate() const;

    /// Reads the keys of `reader`'s object (each spelled like a field; absent
    /// keys keep the default), then calls reader.finish() and validate().
    /// Throws ConfigError naming the key path on a bad or unknown key.
    static DnnConfig from_json(JsonReader& reader);
};

}  // namespace stepstone::nn
