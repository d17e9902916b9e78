#pragma once

#include <cstddef>

namespace stepstone::kb {

/// Number of interleaved partial sums of squared_distance().
inline constexpr std::size_t kDistanceLanes = 8;

/// Squared Euclidean distance between two segments of `dim` floats, in double.
///
/// The order of the floating-point operations is fixed, so the result does not
/// depend on the compiler's vectorisation (the project builds with
/// -ffp-contract=off): each difference a[k] - b[k] is taken in double and its
/// square added to lane k % 8 (lanes start at 0 and accumulate in increasing
/// k); the lanes are then summed as ((l0 + l1) + (l2 + l3)) + ((l4 + l5) + (l6 + l7)).
/// Every nearest-neighbour answer of the knowledge base is defined by this value.
double squared_distance(const float* a, const float* b, std::size_t dim);

/// squared_distance(a, b, dim) if it is <= `bound`; otherwise some value
/// greater than `bound` (the sum may stop early: lane sums only grow, so a
/// partial total above the bound proves the full one is above it too).
double squared_distance_up_to(const float* a, const float* b, std::size_t dim, double bound);

}  // namespace stepstone::kb
