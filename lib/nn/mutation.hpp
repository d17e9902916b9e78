#pragma once

#include <cstddef>

#include "core/rng.hpp"
#include "nn/dnn_config.hpp"
#include "nn/genome.hpp"

namespace stepstone::nn {

/// What one call of mutate() changed.
struct MutationReport {
    std::size_t weights_mutated = 0;
    std::size_t biases_mutated = 0;
    bool rewired_connection = false;
    bool added_connection = false;
    bool deleted_connection = false;
    bool added_neuron = false;
    bool deleted_neuron = false;
};

/// nn2's gen::Dnn::mutate (docs/original.md: network), in this order:
/// 1. mutate_weights, then rewire_one_connection;
/// 2. mutate_biases;
/// 3. with add_connection_rate, add_random_connection;
/// 4. with delete_connection_rate, delete_random_connection;
/// 5. with add_neuron_rate, add_neuron_on_connection;
/// 6. with delete_neuron_rate, delete_random_neuron.
/// Every draw comes from `rng`.
MutationReport mutate(Genome& genome, const DnnConfig& config, Rng& rng);

/// sferes2's EvoFloat polynomial mutation in its simple form: r ~ U[0, 1),
/// delta = (2r)^(1/(eta+1)) - 1 if r < 0.5 else 1 - (2(1-r))^(1/(eta+1)),
/// result clip(gene + delta, 0, 1). Always changes the gene (one draw). The
/// power is std::pow, or portable::pow when `math` says so.
double polynomial_mutation(double gene, double eta, Rng& rng, Math math = Math::portable);

/// Each weight gene mutates with parameter_mutation_rate. Returns the count mutated.
std::size_t mutate_weights(Genome& genome, const DnnConfig& config, Rng& rng);

/// nn2 _change_conns' second loop: visiting the edges in order, each is
/// rewired with rewire_connection_rate and the first one rewired ends the
/// call. A coin chooses whether its source or its target is redrawn (uniform
/// over the valid neurons, up to V^2 attempts to avoid a duplicate edge; the
/// old endpoint may come back). The weight is kept. Returns true if an edge
/// was drawn for rewiring. If every attempt hit a duplicate the edge is left
/// unchanged (nn2 would drop it).
bool rewire_one_connection(Genome& genome, const DnnConfig& config, Rng& rng);

/// Each bias gene, of every neuron, mutates with parameter_mutation_rate.
/// Returns the count mutated.
std::size_t mutate_biases(Genome& genome, const DnnConfig& config, Rng& rng);

/// nn2 _add_conn_nodup: draws a valid (source, target) pair up to V^2 times
/// until it is not an existing edge, then adds it with a uniform weight gene.
/// Returns false (genome unchanged) if every attempt hit an existing edge.
bool add_random_connection(Genome& genome, Rng& rng);

/// nn2 _del_conn: removes a uniformly chosen edge. False if there is none.
bool delete_random_connection(Genome& genome, Rng& rng);

/// nn2 _add_neuron_on_conn: removes a uniformly chosen edge s -> t, adds a
/// hidden neuron n with a uniform bias gene, then s -> n and n -> t, both with
/// the old weight. False if there is no edge.
bool add_neuron_on_connection(Genome& genome, Rng& rng);

/// nn2 _del_neuron: removes a uniformly chosen hidden neuron and its edges.
/// False if there is no hidden neuron.
bool delete_random_neuron(Genome& genome, Rng& rng);

}  // namespace stepstone::nn
