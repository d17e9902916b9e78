#pragma once

// `kb` cases of stepstone bench: the knowledge base's exact index against
// brute force, on realistic synthetic behaviours and on uniform noise, and
// against FLANN's approximate kd-forest.

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "bench/registry.hpp"
#include "kb/knowledge_base.hpp"

namespace stepstone::bench {

/// Segments of one policy in the kb workloads: 4000 steps in windows of 20.
inline constexpr std::size_t kSegmentsPerPolicy = 200;

/// Seconds of the steady clock since `start`.
double seconds_since(std::chrono::steady_clock::time_point start);

/// Registers `kb` (one paper generation's observe step: index vs batched brute
/// force), `kb-uniform` (uniform random
/// values, index vs batched brute force), `kb-load` (building a KB and its
/// index from arrays vs copying the arrays) and `kb-flann` (add_kb_flann_case).
void add_kb_cases(Registry& registry);

/// `policies` synthetic behaviours of `steps` x 15 channels (row-major, values
/// in [0, 1]): 3 lasers from a robot driving in a 600 x 400 box (smooth), 6
/// light sensors (on while an object lies in their cone, so they switch rarely), 2 bumpers (on while pushing
/// a wall), a carrying flag switching rarely, and 3 smooth effectors (wheels, action). Every policy starts
/// from the same pose and descends from one of 40 fixed lineages (a driving style and a controller reaction
/// shared by every seed), slightly mutated, as the policies of one run are. Deterministic in `seed`.
std::vector<float> synthetic_behaviours(std::uint64_t seed, std::size_t policies, std::size_t steps);

/// Numbers reported in docs/knowledge_base.md, measured once each.
struct KbMeasurements {
    std::size_t kb_size = 0;                   ///< segments in the KB before the generation
    std::size_t queries = 0;                   ///< segments observed (one generation)
    std::size_t inserted = 0;                  ///< of which inserted
    double observe_seconds = 0;                ///< the generation's observe step with the index
    double index_queries_per_s = 0;            ///< queries / observe_seconds
    double batched_queries_per_s = 0;          ///< batched brute force on the same workload (a slice)
    double candidates_per_query = 0;           ///< segments passing the lower bound per query
    double uniform_index_queries_per_s = 0;    ///< uniform data, index (brute-force fallback)
    double uniform_batched_queries_per_s = 0;  ///< uniform data, batched brute force
    std::size_t load_segments = 0;             ///< segments of the load test
    double load_seconds = 0;                   ///< from_segments: validate, copy, build the index
    double copy_seconds = 0;                   ///< copying the same arrays
    double bytes_per_segment = 0;              ///< KnowledgeBase::bytes_per_segment() at paper size
};

/// Measures every number of KbMeasurements (Size::quick: smaller KBs).
KbMeasurements measure_kb(Size size);

/// The realistic workload of the `kb` case: its KB (32,580 segments grown from
/// earlier synthetic generations; Size::quick: 4,000) and the segments of the
/// generation it observes (200 policies x 200 segments; Size::quick: 20
/// policies), back to back, 300 values each.
struct KbQueries {
    kb::KnowledgeBase kb;
    std::vector<float> queries;
};
KbQueries kb_queries(Size size);

/// Registers `kb-flann`: lookups (KnowledgeBase::lookup, the path of r_max)
/// of one generation's segments against FLANN's randomized kd-forest (4 trees,
/// 128 checks, 1 nearest neighbour) on the same KB. Defined in
/// bench_kb_flann.cpp.
void add_kb_flann_case(Registry& registry);

/// Numbers of the `kb-flann` case reported in docs/knowledge_base.md.
struct KbFlannMeasurements {
    std::size_t kb_size = 0;           ///< segments in the KB
    std::size_t queries = 0;           ///< query segments (one generation)
    double kb_build_seconds = 0;       ///< KnowledgeBase::from_segments (validation, copy, exact index)
    double flann_build_seconds = 0;    ///< flann::Index::buildIndex, 4 randomized trees
    double lookup_queries_per_s = 0;   ///< KnowledgeBase::lookup, within delta
    double nearest_queries_per_s = 0;  ///< KnowledgeBase::nearest, whatever the distance
    double flann_queries_per_s = 0;    ///< FLANN knnSearch, 1 neighbour, 128 checks
    double recall = 0;                 ///< fraction of queries whose FLANN neighbour is the exact nearest
    double match_agreement = 0;  ///< fraction whose within-delta match (segment or none) FLANN gets right
    double within_delta = 0;     ///< fraction of queries with a KB segment within delta
};

/// Measures every number of KbFlannMeasurements once (Size::quick: smaller KB).
KbFlannMeasurements measure_kb_flann(Size size);

}  // namespace stepstone::bench
