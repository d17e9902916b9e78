#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "kb/knowledge_base.hpp"
#include "kb/segments.hpp"

namespace stepstone::kb {

/// The "20 closest" of the paper's delta rule.
inline constexpr std::size_t kDefaultNeighbours = 20;

/// The paper's delta rule (section III.E: "the mean distance between the 20
/// closest behaviors during 4000 time steps of a successful behavior").
///
/// Reading: for each segment of the policy, the mean Euclidean distance to its
/// `neighbours` nearest other segments of the same policy; delta is the mean
/// of that value over all segments. If the policy has n <= neighbours
/// segments, each uses its n - 1 others. Throws DataError if the policy has
/// fewer than 2 segments, neighbours is 0, or a value is not finite.
double calibrate_delta(Segments policy, std::size_t neighbours = kDefaultNeighbours);

/// KB size obtained with one delta.
struct DeltaSize {
    double delta = 0.0;     ///< the threshold tried
    std::size_t size = 0;   ///< segments in the KB after observing every policy
};

/// For each delta, the size of a KB (params with that delta) fed with
/// `policies` in order (rewards do not affect the size, so 0 is used).
/// Throws ConfigError for an invalid delta and DataError for bad segments.
std::vector<DeltaSize> kb_sizes(const KbParams& params, std::span<const Segments> policies,
                                std::span<const double> deltas);

}  // namespace stepstone::kb
