#pragma once

// Converts the bench's edge-list networks into lib/nn genomes, so the pointer
// baseline and nn::Network run the very same network.

#include "nn/dnn_config.hpp"
#include "nn/genome.hpp"
#include "nn/network.hpp"
#include "reference/pointer_network.hpp"

namespace stepstone::bench {

/// The genome whose developed weights and biases (with `config`'s ranges)
/// are those of `spec`: gene = (value - min) / (max - min). Neuron numbering
/// is the same (inputs, outputs, hidden).
nn::Genome genome_from_spec(const reference::NetworkSpec& spec, const nn::DnnConfig& config = {});

/// Throws DataError if the two networks' outputs differ by more than 1e-4 on
/// the first three steps after a reset, for 100 pseudo-random input
/// sequences (a sanity check that both sides of a case compute the same
/// function; longer runs of a recurrent network may amplify rounding).
/// Resets both afterwards.
void check_same_network(reference::PointerNetwork& baseline, nn::Network& candidate, int inputs, int outputs);

}  // namespace stepstone::bench
