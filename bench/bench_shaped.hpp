#pragma once

// `shaped-*` cases of stepstone bench: what shaping adds to a generation.

#include <array>
#include <cstddef>

#include "bench/registry.hpp"

namespace stepstone::bench {

/// The deltas of the shaped cases: the paper's and the rule's.
inline constexpr std::array<double, 2> kShapedDeltas{1.83, 3.84};

/// Registers `shaped-1.83` and `shaped-3.84`: a target-task generation of
/// population 100 (restored from bench/data/generation.json, so both sides
/// evaluate the same children, on one thread) unshaped as the baseline and
/// shaped by `sum` as the candidate. The KB is grown by replaying the 500
/// source-run genomes of bench/data/source_genomes.jsonl on the source
/// task and observing them at delta 1.83; the 3.84 one is it coarsened.
/// scripts/bench-fixture regenerates both files from a run.
void add_shaped_cases(Registry& registry);

/// Size of the KB a shaped case uses, for docs/performance.md.
struct ShapedKbShape {
    std::size_t segments = 0;  ///< segments in the KB
    std::size_t positive = 0;  ///< of which average more than 0
};
ShapedKbShape shaped_kb_shape(Size size, double delta);

}  // namespace stepstone::bench
