#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "core/rng.hpp"
#include "evo/pareto.hpp"

namespace stepstone::evo {

/// sferes2's NSGA-II binary tournament (docs/original.md: NSGA-II): the one that
/// dominates wins; otherwise the larger crowding distance; otherwise a coin
/// flip from `rng`. Ranks are not compared. Returns a or b.
std::size_t tournament(std::size_t a, std::size_t b, const Objectives& objectives,
                       std::span<const double> crowding, Rng& rng);

/// Mating selection of one epoch (docs/original.md: NSGA-II): two random permutations
/// a1, a2 of the parents; for every block of 4 positions i, the winners of
/// (a1[i], a1[i+1]), (a1[i+2], a1[i+3]), (a2[i], a2[i+1]), (a2[i+2], a2[i+3]).
/// Returns one parent index per child, in child order: children 2k and 2k+1
/// come from the pair (result[2k], result[2k+1]) (copies, or a crossover).
/// `crowding` is each parent's crowding distance from the environmental
/// selection that chose it (Survivors::crowding). Draws: the permutation a1,
/// then a2, then the tie coins in tournament order, all from `rng`.
/// Throws DataError unless the population size is a positive multiple of 4
/// and crowding has one value per parent.
std::vector<std::size_t> select_parents(const Objectives& objectives, std::span<const double> crowding,
                                        Rng& rng);

/// The individuals kept by environmental selection, in sferes2's order.
struct Survivors {
    /// Indices into the mixed population.
    std::vector<std::size_t> indices;
    /// Crowding distance of each kept individual within its front of the
    /// mixed population: the value select_parents needs next generation.
    std::vector<double> crowding;
    /// Front rank of each kept individual (0 = non-dominated).
    std::vector<std::size_t> rank;
};

/// NSGA-II environmental selection (Deb et al. 2002; docs/original.md: NSGA-II):
/// whole fronts are taken while their total stays below `count`; the first
/// front that does not fit is sorted by crowding, descending (ties by index),
/// and its best fill the rest. This is the (mu + lambda) replacement when
/// `objectives` holds parents and children, and the cut of the 2 x mu random
/// individuals at generation 0. Throws DataError if count > objectives.size().
Survivors survivors(const Objectives& objectives, std::size_t count);

}  // namespace stepstone::evo
