#pragma once

#include <cstddef>
#include <span>
#include <vector>

namespace stepstone::evo {

/// Objective vectors, one per individual, all of the same length. Every
/// objective is maximised.
using Objectives = std::vector<std::vector<double>>;

/// Crowding distance given to the boundary individuals of a front (sferes2
/// crowd.hpp's `inf`, docs/original.md: NSGA-II).
inline constexpr double kBoundaryCrowding = 1e14;

/// Pareto dominance for maximisation: a is >= b everywhere and > somewhere.
bool dominates(std::span<const double> a, std::span<const double> b);

/// Deb's fast non-dominated sort (Deb et al. 2002, NSGA-II, O(M N^2)).
/// Front 0 holds the individuals nobody dominates, front k those dominated
/// only by members of fronts < k. Within a front, indices are increasing.
std::vector<std::vector<std::size_t>> non_dominated_fronts(const Objectives& objectives);

/// Crowding distance of the members of one front (docs/original.md: NSGA-II, sferes2
/// crowd.hpp): fronts of 1 or 2 members are all kBoundaryCrowding; otherwise
/// for each objective in turn, the front is sorted ascending (ties by index),
/// both ends are set to kBoundaryCrowding and each interior member adds
/// (f_next - f_prev) / (f_max - f_min), nothing if the range is 0.
/// result[k] belongs to front[k].
std::vector<double> crowding_distance(const Objectives& objectives, std::span<const std::size_t> front);

/// Fronts, per-individual rank and per-individual crowding (within its front).
struct Ranking {
    std::vector<std::vector<std::size_t>> fronts;
    std::vector<std::size_t> rank;
    std::vector<double> crowding;
};

/// non_dominated_fronts plus crowding_distance on every front.
Ranking rank_and_crowd(const Objectives& objectives);

}  // namespace stepstone::evo
