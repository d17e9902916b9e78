#include "reference/pointer_network.hpp"

#include <catch2/catch.hpp>
#include <set>
#include <stdexcept>
#include <utility>

using namespace stepstone::reference;

TEST_CASE("the pointer network equals a hand-computed tiny recurrent network", "[bench][nn]") {
    // neurons: 0 input, 1 output, 2 hidden with a self-loop
    NetworkSpec spec;
    spec.inputs = 1;
    spec.outputs = 1;
    spec.hidden = 1;
    spec.biases = {0.0f, 0.2f, -0.1f};
    spec.edges = {{0, 2, 2.0f}, {2, 1, 1.5f}, {0, 1, -1.0f}, {2, 2, 0.5f}};
    PointerNetwork network(spec);
    const float in = 1.0f;
    float out = 0;

    // step 1, states 0: hidden = s(2 * 1 - 5 * -0.1) = s(2.5) = 0.924142;
    // output = s(-1 * 1 - 5 * 0.2) = s(-2) = 0.119203 (input edges act at once)
    network.step(&in, &out);
    CHECK(out == Approx(0.119202922).epsilon(1e-6));
    // step 2: hidden = s(2 + 0.5 * 0.924142 + 0.5) = 0.950831;
    // output = s(1.5 * 0.924142 - 1 - 1) = s(-0.613787) = 0.351196
    network.step(&in, &out);
    CHECK(out == Approx(0.351195755).epsilon(1e-6));

    // reset: the first step again
    network.reset();
    network.step(&in, &out);
    CHECK(out == Approx(0.119202922).epsilon(1e-6));
}

TEST_CASE("a neuron without inputs outputs 1 / (1 + exp(5 b))", "[bench][nn]") {
    NetworkSpec spec;
    spec.inputs = 1;
    spec.outputs = 1;
    spec.biases = {0.0f, 0.1f};
    PointerNetwork network(spec);
    const float in = 0.3f;
    float out = 0;
    network.step(&in, &out);
    // 1 / (1 + e^0.5) = 0.377541
    CHECK(out == Approx(0.377540669).epsilon(1e-6));
}

TEST_CASE("random network specs have distinct valid edges and weights in range", "[bench][nn]") {
    const auto spec = random_network_spec(12, 15, 3, 120, 7);
    CHECK(spec.neurons() == 30);
    REQUIRE(spec.edges.size() == 120);
    std::set<std::pair<int, int>> seen;
    for (const auto& e : spec.edges) {
        CHECK((e.source < 12 || e.source >= 15));  // inputs or hidden
        CHECK(e.target >= 12);                     // outputs or hidden
        CHECK(e.weight >= -5.0f);
        CHECK(e.weight <= 5.0f);
        seen.insert({e.source, e.target});
    }
    CHECK(seen.size() == 120);
    // deterministic in the seed
    CHECK(random_network_spec(12, 15, 3, 120, 7).edges[5].weight == spec.edges[5].weight);
    // 27 sources x 18 targets = 486 pairs at most
    CHECK_THROWS_AS(random_network_spec(12, 15, 3, 487, 7), std::invalid_argument);
    PointerNetwork network(spec);
    float in[12] = {};
    float out[3];
    network.step(in, out);
    for (float o : out) {
        CHECK(o > 0.0f);
        CHECK(o < 1.0f);
    }
}

TEST_CASE("an edge into an input is refused", "[bench][nn]") {
    NetworkSpec spec;
    spec.inputs = 2;
    spec.outputs = 1;
    spec.biases = {0, 0, 0};
    spec.edges = {{2, 0, 1.0f}};
    CHECK_THROWS_AS(PointerNetwork(spec), std::invalid_argument);
}
