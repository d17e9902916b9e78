#pragma once

// `kb` cases of stepstone bench: the knowledge base's exact index against
// brute force, on realistic synthetic behaviours and on uniform noise.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "bench/registry.hpp"

namespace stepstone::bench {

/// Registers `kb` (one paper generation's observe step: index vs batched brute
/// force), `kb-loop` (same, vs a plain loop), `kb-uniform` (uniform random
/// values, index vs batched brute force) and `kb-load` (building a KB and its
/// index from arrays vs copying the arrays).
void add_kb_cases(Registry& registry);

/// `policies` synthetic behaviours of `steps` x 15 channels (row-major, values
/// in [0, 1]): 3 lasers from a robot driving in a 600 x 400 box (smooth), 6
/// light sensors (on while an object lies in their cone, so they switch rarely), 2 bumpers (on while pushing a wall), a
/// carrying flag switching rarely, and 3 smooth effectors (wheels, action).
/// Every policy starts from the same pose and descends from one of 40 fixed
/// lineages (a driving style and a controller reaction shared by every seed),
/// slightly mutated, as the policies of one run are. Deterministic in `seed`.
std::vector<float> synthetic_behaviours(std::uint64_t seed, std::size_t policies, std::size_t steps);

/// Numbers reported in docs/knowledge_base.md, measured once each.
struct KbMeasurements {
    std::size_t kb_size = 0;              ///< segments in the KB before the generation
    std::size_t queries = 0;              ///< segments observed (one generation)
    std::size_t inserted = 0;             ///< of which inserted
    double observe_seconds = 0;           ///< the generation's observe step with the index
    double index_queries_per_s = 0;       ///< queries / observe_seconds
    double batched_queries_per_s = 0;     ///< batched brute force on the same workload (a slice)
    double loop_queries_per_s = 0;        ///< plain loop (a slice)
    double candidates_per_query = 0;      ///< segments passing the lower bound per query
    double uniform_index_queries_per_s = 0;    ///< uniform data, index (brute-force fallback)
    double uniform_batched_queries_per_s = 0;  ///< uniform data, batched brute force
    std::size_t load_segments = 0;        ///< segments of the load test
    double load_seconds = 0;              ///< from_segments: validate, copy, build the index
    double copy_seconds = 0;              ///< copying the same arrays
    double bytes_per_segment = 0;         ///< KnowledgeBase::bytes_per_segment() at paper size
};

/// Measures every number of KbMeasurements (Size::quick: smaller KBs).
KbMeasurements measure_kb(Size size);

}  // namespace stepstone::bench
