#include <catch2/catch.hpp>

#include <cmath>

#include "nn/mutation.hpp"
#include "support.hpp"

using namespace stepstone;
using namespace stepstone::nn;

namespace {

// the perceptron with three connections split by hidden neurons: every
// structural operator has room to act
Genome roomy_genome(Rng& rng) {
    Genome genome = Genome::random_perceptron(DnnConfig{}, rng);
    for (int k = 0; k < 3; ++k) add_neuron_on_connection(genome, rng);
    return genome;
}

}  // namespace

TEST_CASE("polynomial mutation moves a gene with the eta 15 distribution", "[nn][mutation]") {
    // with eta = 15, P(|delta| > x) = (1 - x)^16 (half from each side), so
    // P(|delta| > 0.1) = 0.9^16 = 0.18530 and P(|delta| > 0.3) = 0.7^16 = 0.0033233
    Rng rng(3);
    const int n = 100000;
    int beyond_01 = 0, beyond_03 = 0, below = 0;
    for (int k = 0; k < n; ++k) {
        const double gene = polynomial_mutation(0.5, 15.0, rng);
        REQUIRE(gene >= 0.0);
        REQUIRE(gene <= 1.0);
        beyond_01 += std::abs(gene - 0.5) > 0.1;
        beyond_03 += std::abs(gene - 0.5) > 0.3;
        below += gene < 0.5;
    }
    // tolerances: about 5 standard deviations of a binomial proportion at n = 1e5
    CHECK(beyond_01 / double(n) == Approx(0.18530).margin(0.0062));
    CHECK(beyond_03 / double(n) == Approx(0.0033233).margin(0.0009));
    CHECK(below / double(n) == Approx(0.5).margin(0.008));
}

TEST_CASE("polynomial mutation clips at the gene bounds", "[nn][mutation]") {
    // from 0 half the draws go negative and clip to 0 (sferes2's simple form)
    Rng rng(4);
    int zeros = 0;
    for (int k = 0; k < 20000; ++k) zeros += polynomial_mutation(0.0, 15.0, rng) == 0.0;
    CHECK(zeros / 20000.0 == Approx(0.5).margin(0.018));
}

TEST_CASE("weights and biases each mutate with the configured rate", "[nn][mutation]") {
    // every gene at 0.5 changes when mutated (delta is 0 with probability 0)
    Rng rng(5);
    const DnnConfig config;
    std::size_t weights = 0, weights_changed = 0, biases = 0, biases_changed = 0;
    for (int trial = 0; trial < 2000; ++trial) {
        Genome genome = roomy_genome(rng);
        for (std::size_t k = 0; k < genome.connection_count(); ++k) genome.connection(k).weight = 0.5;
        for (auto& b : genome.biases()) b = 0.5;
        const Genome before = genome;
        mutate_weights(genome, config, rng);
        mutate_biases(genome, config, rng);
        for (std::size_t k = 0; k < genome.connection_count(); ++k) {
            ++weights;
            weights_changed += genome.connections()[k].weight != 0.5;
        }
        for (double b : genome.biases()) {
            ++biases;
            biases_changed += b != 0.5;
        }
        REQUIRE(genome.connection_count() == before.connection_count());
    }
    // rate 0.1 (docs/original.md: network); n is 78,000 weights and 36,000 biases: 5 sd < 0.008
    CHECK(static_cast<double>(weights_changed) / static_cast<double>(weights) == Approx(0.1).margin(0.006));
    CHECK(static_cast<double>(biases_changed) / static_cast<double>(biases) == Approx(0.1).margin(0.008));
}

TEST_CASE("rewiring changes at most one edge, keeps its weight and one endpoint", "[nn][mutation]") {
    Rng rng(6);
    const DnnConfig config;
    int drawn = 0;
    const int trials = 20000;
    for (int trial = 0; trial < trials; ++trial) {
        Genome genome = Genome::random_perceptron(config, rng);  // 36 edges
        genome.add_hidden(0.5);                                  // room to rewire to
        const Genome before = genome;
        drawn += rewire_one_connection(genome, config, rng);
        nn_test::require_invariants(genome);
        int changed = 0;
        for (std::size_t k = 0; k < genome.connection_count(); ++k) {
            const auto& a = before.connections()[k];
            const auto& b = genome.connections()[k];
            if (a == b) continue;
            ++changed;
            CHECK(a.weight == b.weight);
            CHECK((a.source == b.source || a.target == b.target));
        }
        REQUIRE(changed <= 1);
    }
    // P(some edge drawn) = 1 - 0.97^36 = 0.66597; 5 sd at n = 20000 is 0.0167
    CHECK(drawn / double(trials) == Approx(0.66597).margin(0.0167));
}

TEST_CASE("adding a connection adds one valid new edge, or nothing when the graph is full", "[nn][mutation]") {
    Rng rng(7);
    Genome full = Genome::random_perceptron(DnnConfig{}, rng);  // every valid edge of 12 -> 3 exists
    const Genome before = full;
    CHECK_FALSE(add_random_connection(full, rng));
    CHECK(full == before);

    for (int trial = 0; trial < 200; ++trial) {
        Genome genome = roomy_genome(rng);
        const Genome old = genome;
        REQUIRE(add_random_connection(genome, rng));
        REQUIRE(genome.connection_count() == old.connection_count() + 1);
        REQUIRE(std::equal(old.connections().begin(), old.connections().end(), genome.connections().begin()));
        nn_test::require_invariants(genome);
    }
}

TEST_CASE("deleting a connection removes one edge and keeps the order of the others", "[nn][mutation]") {
    Rng rng(8);
    Genome genome = roomy_genome(rng);
    const Genome old = genome;
    REQUIRE(delete_random_connection(genome, rng));
    REQUIRE(genome.connection_count() == old.connection_count() - 1);
    std::size_t j = 0;
    for (const auto& c : old.connections()) {
        if (j < genome.connection_count() && genome.connections()[j] == c) ++j;
    }
    CHECK(j == genome.connection_count());  // the survivors are a subsequence

    Genome empty(2, 2);
    CHECK_FALSE(delete_random_connection(empty, rng));
}

TEST_CASE("adding a neuron splits an edge into two with the old weight", "[nn][mutation]") {
    Rng rng(9);
    for (int trial = 0; trial < 200; ++trial) {
        Genome genome = roomy_genome(rng);
        const Genome old = genome;
        REQUIRE(add_neuron_on_connection(genome, rng));
        REQUIRE(genome.hidden_count() == old.hidden_count() + 1);
        REQUIRE(genome.connection_count() == old.connection_count() + 1);
        const std::size_t n = genome.neuron_count() - 1;
        const auto& in = genome.connections()[genome.connection_count() - 2];
        const auto& out = genome.connections()[genome.connection_count() - 1];
        REQUIRE(in.target == n);
        REQUIRE(out.source == n);
        REQUIRE(in.weight == out.weight);
        // the split edge is gone, the rest unchanged
        REQUIRE_FALSE(genome.has_connection(in.source, out.target));
        REQUIRE(old.has_connection(in.source, out.target));
        nn_test::require_invariants(genome);
    }
}

TEST_CASE("deleting a neuron removes a hidden neuron with its edges", "[nn][mutation]") {
    Rng rng(10);
    Genome genome(1, 1);
    CHECK_FALSE(delete_random_neuron(genome, rng));  // no hidden neuron: nothing happens

    // 0 -> 2 -> 1, 0 -> 3 -> 1: deleting either leaves one path, renumbered to 2
    genome.add_hidden(0.25);
    genome.add_hidden(0.75);
    genome.add_connection(0, 2, 0.1);
    genome.add_connection(2, 1, 0.2);
    genome.add_connection(0, 3, 0.3);
    genome.add_connection(3, 1, 0.4);
    REQUIRE(delete_random_neuron(genome, rng));
    REQUIRE(genome.hidden_count() == 1);
    REQUIRE(genome.connection_count() == 2);
    const bool kept_first = genome.biases()[2] == 0.25;
    const std::vector<Connection> want_first{{0, 2, 0.1}, {2, 1, 0.2}};
    const std::vector<Connection> want_second{{0, 2, 0.3}, {2, 1, 0.4}};
    CHECK(genome.connections() == (kept_first ? want_first : want_second));
}

TEST_CASE("structural operators fire at the configured rates", "[nn][mutation]") {
    const DnnConfig config;
    const int trials = 20000;
    int add_conn = 0, del_conn = 0, add_neuron = 0, del_neuron = 0;
    for (int trial = 0; trial < trials; ++trial) {
        Rng rng(11, 0, static_cast<std::uint64_t>(trial), Purpose::test);
        Genome genome = roomy_genome(rng);
        const auto report = mutate(genome, config, rng);
        add_conn += report.added_connection;
        del_conn += report.deleted_connection;
        add_neuron += report.added_neuron;
        del_neuron += report.deleted_neuron;
        nn_test::require_invariants(genome);
    }
    // docs/original.md (network): 0.15, 0.05, 0.05, 0.05; each operator can act on this genome
    // (add-connection could only fail after V^2 duplicate draws). Margins are 5 sd
    // at n = 20000: 0.0126 for 0.15 and 0.0077 for 0.05
    CHECK(add_conn / double(trials) == Approx(0.15).margin(0.0126));
    CHECK(del_conn / double(trials) == Approx(0.05).margin(0.0077));
    CHECK(add_neuron / double(trials) == Approx(0.05).margin(0.0077));
    CHECK(del_neuron / double(trials) == Approx(0.05).margin(0.0077));
}

TEST_CASE("long mutation chains keep the graph invariants", "[nn][mutation]") {
    Rng rng(12);
    for (int g = 0; g < 100; ++g) {
        Genome genome = nn_test::grown_genome(rng, 60);
        nn_test::require_invariants(genome);
        genome.simplify();
        nn_test::require_invariants(genome);
    }
}

TEST_CASE("a mutation is a function of the genome and the stream", "[nn][mutation][determinism]") {
    Rng seed_rng(13);
    const Genome start = nn_test::grown_genome(seed_rng, 20);
    Genome a = start, b = start;
    Rng ra(99, 5, 7, Purpose::mutation), rb(99, 5, 7, Purpose::mutation);
    for (int k = 0; k < 50; ++k) {
        mutate(a, DnnConfig{}, ra);
        mutate(b, DnnConfig{}, rb);
    }
    CHECK(a == b);
}
