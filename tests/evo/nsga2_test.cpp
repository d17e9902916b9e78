#include "nsga2.hpp"  // examples/zdt1

#include <algorithm>
#include <catch2/catch.hpp>
#include <vector>

#include "core/error.hpp"

using namespace stepstone;
using namespace stepstone::evo;
using namespace example;

namespace {

// two conflicting objectives on [0, 1]^3: be close to 0.2 and close to 0.9
struct Toy {
    using Genome = std::vector<double>;
    Genome random_genome(Rng& rng) const { return {rng.uniform(), rng.uniform(), rng.uniform()}; }
    void mutate(Genome& genome, Rng& rng) const {
        const auto k = static_cast<std::size_t>(rng.below(genome.size()));
        genome[k] = std::clamp(genome[k] + rng.uniform(-0.1, 0.1), 0.0, 1.0);
    }
    std::vector<double> evaluate(const Genome& genome) const {
        double near = 0.0, far = 0.0;
        for (double x : genome) {
            near -= (x - 0.2) * (x - 0.2);
            far -= (x - 0.9) * (x - 0.9);
        }
        return {near, far};
    }
};

double best_first_objective(const Population<Toy::Genome>& population) {
    double best = -1e300;
    for (const auto& o : population.objectives) best = std::max(best, o[0]);
    return best;
}

}  // namespace

TEST_CASE("generation 0 evaluates twice the population and keeps the population", "[evo][nsga2]") {
    const Nsga2<Toy> ea(Toy{}, 20, 7);
    const auto population = ea.initialise();
    CHECK(population.genomes.size() == 20);
    CHECK(population.objectives.size() == 20);
    CHECK(population.crowding.size() == 20);
    CHECK(population.evaluations == 40);  // initial_aleat = 2 (docs/original.md: NSGA-II)
    CHECK(population.generation == 0);
}

TEST_CASE("mu plus lambda elitism never loses the best first objective", "[evo][nsga2]") {
    const Nsga2<Toy> ea(Toy{}, 24, 8);
    auto population = ea.initialise();
    double best = best_first_objective(population);
    const double start = best;
    for (int g = 0; g < 60; ++g) {
        ea.epoch(population);
        const double now = best_first_objective(population);
        REQUIRE(now >= best);
        best = now;
    }
    CHECK(population.evaluations == 48 + 60 * 24);
    CHECK(best > start);  // and it improved
    CHECK(best > -0.01);  // close to the optimum 0 of the first objective
}

TEST_CASE("a population restored from its plain data continues as if uninterrupted", "[evo][nsga2][determinism]") {
    const Nsga2<Toy> ea(Toy{}, 16, 9);
    auto straight = ea.initialise();
    for (int g = 0; g < 6; ++g) ea.epoch(straight);

    auto first_half = ea.initialise();
    for (int g = 0; g < 3; ++g) ea.epoch(first_half);
    Population<Toy::Genome> restored = first_half;  // what a checkpoint stores
    const Nsga2<Toy> resumed_ea(Toy{}, 16, 9);
    for (int g = 0; g < 3; ++g) resumed_ea.epoch(restored);

    CHECK(restored.genomes == straight.genomes);
    CHECK(restored.objectives == straight.objectives);
    CHECK(restored.crowding == straight.crowding);
    CHECK(restored.generation == 6);
}

TEST_CASE("the driver refuses a population that is not a multiple of 4", "[evo][nsga2][errors]") {
    CHECK_THROWS_AS(Nsga2<Toy>(Toy{}, 10, 1), ConfigError);
    CHECK_THROWS_WITH(Nsga2<Toy>(Toy{}, 10, 1),
                      Catch::Matchers::Equals("population_size must be a positive multiple of 4, got 10"));
}
