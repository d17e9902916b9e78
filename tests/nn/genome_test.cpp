#include <catch2/catch.hpp>

#include <algorithm>
#include <string>

#include "core/error.hpp"
#include "nn/genome.hpp"
#include "support.hpp"

using namespace stepstone;
using namespace stepstone::nn;
using Catch::Matchers::Contains;

TEST_CASE("the initial genome is the full 12 to 3 perceptron of collectball", "[nn][genome]") {
    Rng rng(1);
    const Genome genome = Genome::random_perceptron(DnnConfig{}, rng);
    // docs/original.md (network): 12 x 3 = 36 connections, no hidden neuron
    CHECK(genome.input_count() == 12);
    CHECK(genome.output_count() == 3);
    CHECK(genome.hidden_count() == 0);
    CHECK(genome.connection_count() == 36);
    for (std::size_t i = 0; i < 12; ++i) {
        for (std::size_t o = 12; o < 15; ++o) CHECK(genome.has_connection(i, o));
    }
    nn_test::require_invariants(genome);
}

TEST_CASE("genes develop linearly onto the configured range", "[nn][genome]") {
    // g * (max - min) + min with the paper's [-5, 5]
    CHECK(develop(0.0, -5.0, 5.0) == -5.0);
    CHECK(develop(1.0, -5.0, 5.0) == 5.0);
    CHECK(develop(0.5, -5.0, 5.0) == 0.0);
    CHECK(develop(0.25, -5.0, 5.0) == -2.5);
}

TEST_CASE("simplify removes exactly the hidden neurons with no path to an output", "[nn][genome]") {
    // inputs 0,1; output 2; hidden 3..8
    Genome genome(2, 1);
    for (int h = 0; h < 6; ++h) genome.add_hidden(0.5);
    genome.add_connection(0, 3, 0.1);  // 0 -> 3 -> 2: useful
    genome.add_connection(3, 2, 0.2);
    genome.add_connection(1, 4, 0.3);  // 1 -> 4, dead end: removed
    genome.add_connection(5, 2, 0.4);  // 5 -> 2, unreachable from inputs: kept (6.7)
    genome.add_connection(0, 6, 0.5);  // 0 -> 6 -> 7 -> 6, a cycle with no exit: both removed
    genome.add_connection(6, 7, 0.6);
    genome.add_connection(7, 6, 0.7);
    genome.add_connection(8, 8, 0.8);  // 8 -> 8 -> 3: a self-loop feeding a useful neuron: kept
    genome.add_connection(8, 3, 0.9);

    CHECK(genome.simplify() == 3);

    // 3 stays 3, 5 becomes 4, 8 becomes 5
    CHECK(genome.neuron_count() == 6);
    const std::vector<Connection> want{{0, 3, 0.1}, {3, 2, 0.2}, {4, 2, 0.4}, {5, 5, 0.8}, {5, 3, 0.9}};
    CHECK(genome.connections() == want);
    CHECK(genome.simplify() == 0);
}

TEST_CASE("genomes round-trip through JSON exactly", "[nn][genome][json]") {
    Rng rng(2);
    for (int trial = 0; trial < 50; ++trial) {
        Genome genome = nn_test::grown_genome(rng, 30);
        genome.biases()[0] = 0.1;  // not exactly representable: must still come back
        genome.biases()[1] = 1.0 / 3.0;
        const std::string text = genome.to_json().dump();
        const Genome back = Genome::from_json(nlohmann::json::parse(text));
        REQUIRE(back == genome);
        REQUIRE(back.to_json().dump() == text);
    }
}

TEST_CASE("the JSON form is compact and readable", "[nn][genome][json]") {
    Genome genome(1, 1);
    genome.add_connection(0, 1, 0.25);
    genome.biases() = {0.5, 0.75};
    CHECK(genome.to_json().dump() == R"({"biases":[0.5,0.75],"connections":[[0,1,0.25]],"inputs":1,"outputs":1})");
}

TEST_CASE("malformed genome JSON is refused with a one-line message", "[nn][genome][json][errors]") {
    const auto refuse = [](const char* text, const char* message) {
        INFO(text);
        const auto json = nlohmann::json::parse(text);
        REQUIRE_THROWS_AS(Genome::from_json(json), DataError);
        try {
            Genome::from_json(json);
        } catch (const DataError& e) {
            const std::string what = e.what();
            CHECK_THAT(what, Contains(message));
            CHECK(what.find('\n') == std::string::npos);
        }
    };
    refuse("[1, 2]", "genome must be a JSON object");
    refuse(R"({"outputs":1,"biases":[0.5,0.5],"connections":[]})", "missing key \"inputs\"");
    refuse(R"({"inputs":0,"outputs":1,"biases":[0.5],"connections":[]})", "inputs must be a positive integer");
    refuse(R"({"inputs":1,"outputs":1,"biases":[0.5],"connections":[]})", "biases must be an array of at least 2");
    refuse(R"({"inputs":1,"outputs":1,"biases":[0.5,1.5],"connections":[]})", "biases[1] must be in [0, 1]");
    refuse(R"({"inputs":1,"outputs":1,"biases":[0.5,"x"],"connections":[]})", "biases[1] must be a number");
    refuse(R"({"inputs":1,"outputs":1,"biases":[0.5,0.5],"connections":[[0,1]]})",
           "connections[0] must be [source, target, weight]");
    refuse(R"({"inputs":1,"outputs":1,"biases":[0.5,0.5],"connections":[[0,2,0.5]]})",
           "connections[0] target must be a neuron index below 2");
    refuse(R"({"inputs":1,"outputs":1,"biases":[0.5,0.5],"connections":[[1,1,0.5]]})",
           "connections[0] starts at output neuron 1");
    refuse(R"({"inputs":1,"outputs":1,"biases":[0.5,0.5,0.5],"connections":[[2,0,0.5]]})",
           "connections[0] ends at input neuron 0");
    refuse(R"({"inputs":1,"outputs":1,"biases":[0.5,0.5],"connections":[[0,1,0.5],[0,1,0.25]]})",
           "connections[1] duplicates the edge 0 -> 1");
    refuse(R"({"inputs":1,"outputs":1,"biases":[0.5,0.5],"connections":[[0,1,-0.1]]})",
           "connections[0] weight must be in [0, 1]");
    refuse(R"({"inputs":1,"outputs":1,"biases":[0.5,0.5],"connections":[],"extra":1})", "unknown key \"extra\"");
}
