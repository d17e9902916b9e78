#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <utility>
#include <vector>

#include "evo/edit_distance.hpp"

namespace stepstone::evo {

/// Two positions (first < second) of a population whose distance is wanted.
using PositionPair = std::pair<std::uint32_t, std::uint32_t>;

/// Computes the distances of `pairs` between `trajectories` (all of
/// `length`), result k for pair k. Any split of the pairs over threads or
/// processes gives the same values: each is a pure function of its two
/// trajectories.
using PairDistances = std::function<std::vector<float>(
    std::span<const PositionPair> pairs, std::span<const Trajectory> trajectories, std::size_t length)>;

/// The distances of `pairs` on `threads` threads of this process (0 means 1),
/// kLanes pairs a batch; batch b holds pairs [b * kLanes, (b + 1) * kLanes).
std::vector<float> pair_distances(std::span<const PositionPair> pairs,
                                  std::span<const Trajectory> trajectories, std::size_t length,
                                  unsigned threads);

/// The behavioural diversity objective of collectball (docs/original.md: diversity): the
/// full symmetric matrix of edit distances between the trajectories of the
/// mixed population, and each individual's sum of distances to all others.
///
/// Distances are cached by individual id: update() computes only the pairs
/// involving an id that was not in the previous update (in NSGA-II, the
/// parents are survivors of the previous mixed population, so only pairs
/// with a child are new). The cache never changes a result: the distance is
/// a pure function of the two trajectories, so a resumed run that starts
/// with an empty cache gets the same values. New pairs are computed
/// kLanes at a time on `threads` threads, each result written to its slot,
/// so the values do not depend on the thread count.
class DiversityMatrix {
public:
    /// Makes `ids` (unique) the current population with their trajectories
    /// (all of one length). Throws DataError on a repeated id, on sizes that
    /// differ, or on trajectories of different lengths. threads = 0 means 1.
    void update(std::span<const std::uint64_t> ids, std::span<const Trajectory> trajectories,
                unsigned threads = 1);
    /// The same, the new pairs computed by `compute` (e.g. over the ranks of an MPI job).
    void update(std::span<const std::uint64_t> ids, std::span<const Trajectory> trajectories,
                const PairDistances& compute);

    /// Population size of the last update.
    std::size_t size() const { return ids_.size(); }
    /// d(i, j) between positions of the last update (0 on the diagonal).
    float distance(std::size_t i, std::size_t j) const { return matrix_[i * ids_.size() + j]; }
    /// Sum over j != i of d(i, j), in double and in index order: obj[1] of collectball.
    std::vector<double> sums() const;
    /// Pairs computed (not reused) by the last update.
    std::size_t computed_pairs() const { return computed_pairs_; }
    /// Forgets every cached distance.
    void clear();

private:
    std::vector<std::uint64_t> ids_;
    std::vector<float> matrix_;
    std::size_t computed_pairs_ = 0;
};

/// The full distance matrix (row-major, n x n) of `trajectories`, every pair
/// computed with EditDistanceBatch on `threads` threads (0 means 1).
std::vector<float> distance_matrix(std::span<const Trajectory> trajectories, unsigned threads = 1);

/// Row sums of an n x n matrix in double, in index order, skipping the diagonal.
std::vector<double> distance_sums(std::span<const float> matrix, std::size_t n);

}  // namespace stepstone::evo
