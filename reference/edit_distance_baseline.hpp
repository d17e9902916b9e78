#pragma once

// The behavioural distance the original computes (docs/original.md: diversity), the
// original way: one freshly allocated (n + 1) x (m + 1) table per pair and the
// full symmetric matrix of a generation, sequentially. Kept as the baseline of
// `stepstone bench diversity`.

#include <cstdint>
#include <span>
#include <vector>

namespace stepstone::reference {

/// A trajectory sample: a 50 x 50 grid cell.
struct GridCell {
    std::int32_t x = 0;
    std::int32_t y = 0;
};

/// Optimal-string-alignment distance between two cell sequences:
/// insertion and deletion cost 1, substitution costs the Manhattan distance
/// in cells / 12 (0 if equal), a transposition of two adjacent cells costs
/// table[i-2][j-2] + the current substitution cost. Allocates its table.
float edit_distance_baseline(std::span<const GridCell> a, std::span<const GridCell> b);

/// The diversity objective of one generation: for each trajectory, the sum
/// of its distances to all the others, every pair computed once with
/// edit_distance_baseline (n (n - 1) / 2 calls).
std::vector<double> diversity_baseline(const std::vector<std::vector<GridCell>>& trajectories);

/// Random-walk trajectories on the reachable 12 x 8 board: each sample stays
/// or moves to a neighbouring cell. Deterministic in `seed`.
std::vector<std::vector<GridCell>> random_trajectories(int count, int length, std::uint64_t seed);

}  // namespace stepstone::reference
