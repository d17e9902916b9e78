#pragma once

#include <concepts>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "core/rng.hpp"
#include "core/text.hpp"
#include "evo/pareto.hpp"
#include "evo/selection.hpp"

// The example's NSGA-II driver, built from lib/evo's public steps (select_parents, survivors).
// stepstone's own runs are driven by the engine (exp::Evolution); this sequential driver
// serves examples/zdt1 and the tests of those steps (tests/evo/nsga2_test.cpp).
namespace example {

using stepstone::concat;
using stepstone::ConfigError;
using stepstone::Purpose;
using stepstone::Rng;
using stepstone::evo::Objectives;
using stepstone::evo::select_parents;
using stepstone::evo::survivors;

/// The state of an NSGA-II run between generations: plain data that a driver
/// can store and restore to resume exactly.
template <class Genome>
struct Population {
    std::vector<Genome> genomes;
    /// One objective vector per genome (maximised).
    Objectives objectives;
    /// Crowding of each genome from the selection that kept it (Survivors::crowding).
    std::vector<double> crowding;
    /// Generations done; 0 after initialise().
    std::uint64_t generation = 0;
    /// Evaluations so far, the 2 x mu random ones included.
    std::uint64_t evaluations = 0;
};

/// What Nsga2 needs of a problem: a genome type, random genomes, mutation and
/// evaluation to a vector of objectives to maximise. Optionally
/// `void crossover(const Genome&, const Genome&, Genome&, Genome&, Rng&) const`
/// (children start as copies of the parents otherwise, as with nn2's DNN) and
/// `void modify(Objectives& mixed, const std::vector<Genome>& mixed_genomes) const`,
/// run on the mixed population before environmental selection (the place of
/// collectball's diversity modifier).
template <class P>
concept Nsga2Problem = requires(const P& problem, typename P::Genome& genome, Rng& rng) {
    { problem.random_genome(rng) } -> std::same_as<typename P::Genome>;
    problem.mutate(genome, rng);
    { problem.evaluate(std::as_const(genome)) } -> std::convertible_to<std::vector<double>>;
};

/// A sequential reference driver of sferes2's NSGA-II as collectball configures
/// it (docs/original.md: NSGA-II), built from the public steps (select_parents, survivors).
/// Streams: genome k of generation 0 draws from (seed, 0, k, initial_genome);
/// in generation g >= 1 the mating selection draws from (seed, g, 0,
/// selection) and child k from (seed, g, k, mutation) (child 2k's stream also
/// draws the crossover of children 2k and 2k+1). A population restored from
/// its plain data therefore continues exactly as an uninterrupted run.
template <Nsga2Problem P>
class Nsga2 {
public:
    using Genome = typename P::Genome;

    /// `population_size` must be a positive multiple of 4 (ConfigError otherwise).
    Nsga2(P problem, std::size_t population_size, std::uint64_t seed)
        : problem_(std::move(problem)), size_(population_size), seed_(seed) {
        if (size_ == 0 || size_ % 4 != 0) {
            throw ConfigError(concat("population_size must be a positive multiple of 4, got ", size_));
        }
    }

    const P& problem() const { return problem_; }

    /// Generation 0: 2 x population_size random genomes, evaluated, modified,
    /// cut to population_size by survivors() (sferes2 initial_aleat = 2).
    Population<Genome> initialise() const {
        std::vector<Genome> genomes;
        genomes.reserve(2 * size_);
        for (std::size_t k = 0; k < 2 * size_; ++k) {
            Rng rng(seed_, 0, k, Purpose::initial_genome);
            genomes.push_back(problem_.random_genome(rng));
        }
        Population<Genome> next;
        next.evaluations = genomes.size();
        Objectives objectives = evaluate_all(genomes);
        reduce(std::move(genomes), std::move(objectives), next);
        return next;
    }

    /// One epoch (docs/original.md: NSGA-II): mating selection, crossover if the
    /// problem has one, mutation, evaluation of the children, modifier on the
    /// parents + children, (mu + lambda) environmental selection.
    void epoch(Population<Genome>& population) const {
        const std::uint64_t generation = population.generation + 1;
        Rng selection_rng(seed_, generation, 0, Purpose::selection);
        const auto parents = select_parents(population.objectives, population.crowding, selection_rng);

        // children: copies (or crossovers) of the winners, then mutated
        std::vector<Genome> mixed = population.genomes;
        mixed.reserve(2 * size_);
        for (std::size_t k = 0; k < size_; k += 2) {
            Rng first_rng(seed_, generation, k, Purpose::mutation);
            Rng second_rng(seed_, generation, k + 1, Purpose::mutation);
            Genome first = population.genomes[parents[k]];
            Genome second = population.genomes[parents[k + 1]];
            if constexpr (requires { problem_.crossover(first, second, first, second, first_rng); }) {
                const Genome& a = population.genomes[parents[k]];
                const Genome& b = population.genomes[parents[k + 1]];
                problem_.crossover(a, b, first, second, first_rng);
            }
            problem_.mutate(first, first_rng);
            problem_.mutate(second, second_rng);
            mixed.push_back(std::move(first));
            mixed.push_back(std::move(second));
        }

        // only the children are evaluated; parents keep their objectives
        Objectives objectives = population.objectives;
        for (std::size_t k = size_; k < mixed.size(); ++k) {
            objectives.push_back(problem_.evaluate(std::as_const(mixed[k])));
        }
        population.evaluations += size_;
        population.generation = generation;
        reduce(std::move(mixed), std::move(objectives), population);
    }

private:
    Objectives evaluate_all(const std::vector<Genome>& genomes) const {
        Objectives objectives;
        objectives.reserve(genomes.size());
        for (const auto& genome : genomes) objectives.push_back(problem_.evaluate(genome));
        return objectives;
    }

    void reduce(std::vector<Genome> mixed, Objectives objectives, Population<Genome>& out) const {
        if constexpr (requires { problem_.modify(objectives, mixed); }) {
            problem_.modify(objectives, mixed);
        }
        auto kept = survivors(objectives, size_);
        out.genomes.clear();
        out.objectives.clear();
        for (std::size_t index : kept.indices) {
            out.genomes.push_back(std::move(mixed[index]));
            out.objectives.push_back(std::move(objectives[index]));
        }
        out.crowding = std::move(kept.crowding);
    }

    P problem_;
    std::size_t size_;
    std::uint64_t seed_;
};

}  // namespace example
