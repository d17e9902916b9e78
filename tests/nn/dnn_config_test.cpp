#include <catch2/catch.hpp>

#include "core/error.hpp"
#include "nn/dnn_config.hpp"

using namespace stepstone;
using namespace stepstone::nn;
using Catch::Matchers::Equals;

namespace {

DnnConfig parse(const char* text) {
    const auto json = nlohmann::json::parse(text);
    JsonReader root(json, "");
    auto reader = root.child("dnn");
    return DnnConfig::from_json(reader);
}

}  // namespace

TEST_CASE("the defaults are the paper's DNN settings", "[nn][config]") {
    // docs/original.md: network; docs/runs.md
    const DnnConfig c;
    CHECK(c.inputs == 12);
    CHECK(c.outputs == 3);
    CHECK(c.weight_min == -5.0);
    CHECK(c.weight_max == 5.0);
    CHECK(c.bias_min == -5.0);
    CHECK(c.bias_max == 5.0);
    CHECK(c.bias_scale == 5.0);
    CHECK(c.parameter_mutation_rate == 0.1);
    CHECK(c.polynomial_eta == 15.0);
    CHECK(c.rewire_connection_rate == 0.03);
    CHECK(c.add_connection_rate == 0.15);
    CHECK(c.delete_connection_rate == 0.05);
    CHECK(c.add_neuron_rate == 0.05);
    CHECK(c.delete_neuron_rate == 0.05);
    CHECK_NOTHROW(c.validate());
}

TEST_CASE("the DNN config reads keys spelled like its fields", "[nn][config]") {
    const auto c = parse(R"({"dnn": {"add_neuron_rate": 0.2, "weight_min": -2, "inputs": 4}})");
    CHECK(c.add_neuron_rate == 0.2);
    CHECK(c.weight_min == -2.0);
    CHECK(c.inputs == 4);
    CHECK(c.delete_neuron_rate == 0.05);
}

TEST_CASE("bad DNN settings are refused with the key path", "[nn][config][errors]") {
    CHECK_THROWS_AS(parse(R"({"dnn": {"add_neuron_rte": 0.2}})"), ConfigError);
    CHECK_THROWS_WITH(parse(R"({"dnn": {"add_neuron_rte": 0.2}})"), Equals("dnn.add_neuron_rte: unknown key"));
    CHECK_THROWS_WITH(parse(R"({"dnn": {"delete_connection_rate": -0.1}})"),
                      Equals("dnn.delete_connection_rate must be in [0, 1], got -0.1"));
    CHECK_THROWS_WITH(parse(R"({"dnn": {"weight_min": 5}})"),
                      Equals("dnn.weight_min must be < dnn.weight_max, got 5 and 5"));
    CHECK_THROWS_WITH(parse(R"({"dnn": {"outputs": 0}})"), Equals("dnn.outputs must be in [1, 1048576], got 0"));

    DnnConfig c;
    c.polynomial_eta = -1.0;
    CHECK_THROWS_WITH(c.validate(), Equals("polynomial_eta must be >= 0, got -1"));
    c = DnnConfig{};
    c.add_connection_rate = 1.5;
    CHECK_THROWS_WITH(c.validate(), Equals("add_connection_rate must be in [0, 1], got 1.5"));
}
