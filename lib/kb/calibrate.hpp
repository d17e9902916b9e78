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

/// The delta rule read over windows instead of segments: each of the
/// behaviour's windows of `width` rows at stride 1 (steps - width + 1 of them)
/// takes the mean Euclidean distance to its `neighbours` nearest other
/// windows, and delta is the mean over windows. Two variants, both computed:
/// the candidates are every other window, or only the windows that share no
/// row with it (|i - j| >= width). A window with fewer candidates than
/// `neighbours` uses all it has.
struct WindowDeltas {
    std::size_t windows = 0;         ///< steps - width + 1
    double excluding_overlap = 0.0;  ///< candidates: windows sharing no row with it
    double including_overlap = 0.0;  ///< candidates: every other window
};

/// The windows reading of the rule on a behaviour matrix (row-major, one row a
/// step, `channels` columns). Distances are summed in double. Throws DataError
/// if channels, width or neighbours is 0, behaviour.size() is not a multiple of
/// channels, a value is not finite, or there are fewer than 3 x width - 1
/// steps (some window would have no candidate sharing no row with it).
WindowDeltas calibrate_delta_windows(std::span<const float> behaviour, std::size_t channels,
                                     std::size_t width, std::size_t neighbours = kDefaultNeighbours);

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
