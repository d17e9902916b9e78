#include <catch2/catch.hpp>

#include "core/config.hpp"
#include "core/error.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;
using Catch::Matchers::Equals;

namespace {

struct Ea {
    int population_size = 200;
    double mutation_rate = 0.1;
    std::string treatment = "none";
    bool verbose = false;
};

Ea parse(const std::string& text) {
    const auto json = nlohmann::json::parse(text);
    JsonReader root(json, "");
    Ea ea;
    auto reader = root.child("ea");
    reader.read("population_size", ea.population_size, 4, 100000);
    reader.read("mutation_rate", ea.mutation_rate, 0.0, 1.0);
    reader.read_choice("treatment", ea.treatment, {"none", "sum", "mo"});
    reader.read("verbose", ea.verbose);
    reader.finish();
    root.finish();
    return ea;
}

}  // namespace

TEST_CASE("absent keys keep their defaults, present keys are read", "[core][config]") {
    auto ea = parse(R"({"ea": {"population_size": 40}})");
    CHECK(ea.population_size == 40);
    CHECK(ea.mutation_rate == 0.1);
    CHECK(ea.treatment == "none");
    ea = parse(R"({"ea": {"mutation_rate": 0.25, "treatment": "mo", "verbose": true}})");
    CHECK(ea.mutation_rate == 0.25);
    CHECK(ea.treatment == "mo");
    CHECK(ea.verbose);
}

TEST_CASE("config errors name the key path and the value", "[core][config][errors]") {
    CHECK_THROWS_WITH(parse(R"({"ea": {"populaton_size": 40}})"), Equals("ea.populaton_size: unknown key"));
    CHECK_THROWS_WITH(parse(R"({"ea": {}, "extra": 1})"), Equals("extra: unknown key"));
    CHECK_THROWS_WITH(parse(R"({"ea": {"population_size": "40"}})"),
                      Equals("ea.population_size must be an integer, got \"40\""));
    CHECK_THROWS_WITH(parse(R"({"ea": {"population_size": 2.5}})"),
                      Equals("ea.population_size must be an integer, got 2.5"));
    CHECK_THROWS_WITH(parse(R"({"ea": {"population_size": 2}})"),
                      Equals("ea.population_size must be in [4, 100000], got 2"));
    CHECK_THROWS_WITH(parse(R"({"ea": {"mutation_rate": -0.1}})"),
                      Equals("ea.mutation_rate must be in [0, 1], got -0.1"));
    CHECK_THROWS_WITH(parse(R"({"ea": {"treatment": "best"}})"),
                      Equals("ea.treatment must be one of none|sum|mo, got \"best\""));
    CHECK_THROWS_WITH(parse(R"({"ea": {"verbose": 1}})"), Equals("ea.verbose must be true or false, got 1"));
    CHECK_THROWS_WITH(parse(R"({"ea": [1, 2]})"), Equals("ea must be a JSON object, got [1,2]"));
    CHECK_THROWS_AS(parse(R"({"ea": {"population_size": 18446744073709551615}})"), ConfigError);
}

TEST_CASE("a config file that is missing or not JSON gives a one-line error", "[core][config][errors]") {
    test::TempDir dir;
    CHECK_THROWS_WITH(load_json_file(dir / "absent.json"), Contains("absent.json: cannot open config file"));
    test::write_file(dir / "bad.json", "{\"a\": 1,\n\"b\": }");
    try {
        load_json_file(dir / "bad.json");
        FAIL("no exception");
    } catch (const ConfigError& e) {
        const std::string what = e.what();
        CHECK_THAT(what, Contains("bad.json: invalid JSON"));
        CHECK(what.find('\n') == std::string::npos);
    }
    test::write_file(dir / "good.json", R"({"x": [1, 2]})");
    CHECK(load_json_file(dir / "good.json")["x"][1] == 2);
}
