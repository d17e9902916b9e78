// EvolveConfig: the strict parse of a run config (the key path named in every
// refusal, docs/runs.md) and the example configs, the paper's carrying the
// paper's values.
#include "runs/evolve_config.hpp"

#include <catch2/catch.hpp>
#include <utility>

#include "core/error.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;

TEST_CASE("bad configs are refused with the file and the key named", "[runs][config][errors]") {
    test::TempDir dir;
    const std::vector<std::pair<std::string, std::string>> cases = {
        {R"({"ea": {"populaton_size": 8}})", "ea.populaton_size: unknown key"},
        {R"({"dnn": {"add_connection_rate": -0.1}})", "dnn.add_connection_rate must be in [0, 1], got -0.1"},
        {R"({"ea": {"population_size": 10}})", "ea.population_size must be a multiple of 4, got 10"},
        {R"({"task": {"kind": "sideways"}})", "task.kind must be one of source|target"},
        {R"({"dnn": {"inputs": 5}})", "dnn.inputs and dnn.outputs must be 12 and 3"},
    };
    for (const auto& [text, message] : cases) {
        INFO(text);
        test::write_file(dir / "c.json", text);
        CHECK_THROWS_AS(runs::EvolveConfig::load(dir / "c.json"), ConfigError);
        CHECK_THROWS_WITH(runs::EvolveConfig::load(dir / "c.json"),
                          Contains("c.json: ") && Contains(message));
    }
}

TEST_CASE("bad kb settings are refused with the key named", "[runs][config][kb][errors]") {
    test::TempDir dir;
    const std::vector<std::pair<std::string, std::string>> cases = {
        {R"({"kb": {"delta": -1}})", "c.json: kb.delta must be > 0, got -1"},
        {R"({"kb": {"period": 0}})", "kb.period must be in [1, "},
        {R"({"task": {"steps_per_start": 10}, "kb": {"segment_width": 20}})",
         "kb.segment_width must be <= task.steps_per_start"},
    };
    for (const auto& [text, message] : cases) {
        INFO(text);
        test::write_file(dir / "c.json", text);
        CHECK_THROWS_WITH(runs::EvolveConfig::load(dir / "c.json"), Contains(message));
    }
}

TEST_CASE("every example run config parses and the paper's carries the paper's values",
          "[runs][config][examples]") {
    const std::filesystem::path examples = std::filesystem::path(STEPSTONE_SOURCE_DIR) / "examples";
    int parsed = 0;
    for (const auto& entry : std::filesystem::directory_iterator(examples)) {
        const auto name = entry.path().filename().string();
        if (name.rfind("source_", 0) != 0 || entry.path().extension() != ".json") continue;
        INFO(name);
        CHECK_NOTHROW(runs::EvolveConfig::load(entry.path()));
        ++parsed;
    }
    CHECK(parsed >= 2);
    // the paper's parameters (docs/runs.md, examples/source_paper.json): population 200, generations 0..4000,
    // 3 x 4000 steps, w = 20, delta = 1.83, period 200
    const auto paper = runs::EvolveConfig::load(examples / "source_paper.json");
    CHECK(paper.ea.population_size == 200);
    CHECK(paper.ea.generations == 4000);
    CHECK(paper.task.steps_per_start * paper.task.starts == 12000);
    REQUIRE(paper.kb);
    CHECK(paper.kb->segment_width == 20);
    CHECK(paper.kb->delta == 1.83);
    CHECK(paper.kb->period == 200);
}

TEST_CASE("transfer.seed: the source relative to the config, its defaults, and its stored form",
          "[runs][config][seed]") {
    test::TempDir dir;
    std::filesystem::create_directories(dir / "configs");
    test::write_file(dir / "configs" / "c.json", R"({"ea": {"population_size": 12},
        "transfer": {"treatment": "none", "seed": {"from": "../runs/source.db"}}})");
    const auto config = runs::EvolveConfig::load(dir / "configs" / "c.json");
    REQUIRE(config.seeding() != nullptr);
    CHECK(config.seeding()->from == dir / "configs" / "../runs/source.db");
    CHECK(config.seeding()->with == runs::SeedWith::population);
    CHECK(config.seeding()->count == 12);  // the population size
    CHECK(config.treatment() == runs::Treatment::none);
    CHECK(config.run_treatment() == runs::Treatment::seed);
    const auto json = config.to_json();
    CHECK(json["transfer"] == nlohmann::json::parse(R"({"treatment": "none", "seed": {"from": ")" +
                                                    (dir / "configs" / "../runs/source.db").string() +
                                                    R"(", "with": "population", "count": 12}})"));
    // the stored form reads back as the same config
    CHECK(runs::EvolveConfig::from_json(json, "stored").to_json() == json);

    test::write_file(dir / "s.json", R"({"transfer": {"treatment": "sum", "kb": "/k.db",
        "seed": {"from": "/abs/source.db", "with": "best", "count": 5, "digest": "ab12"}}})");
    const auto shaped = runs::EvolveConfig::load(dir / "s.json");
    CHECK(shaped.seeding()->from == "/abs/source.db");
    CHECK(shaped.seeding()->with == runs::SeedWith::best);
    CHECK(shaped.seeding()->count == 5);
    CHECK(shaped.seeding()->digest == "ab12");
    CHECK(shaped.run_treatment() == runs::Treatment::seed_sum);
    CHECK(shaped.to_json()["transfer"]["kb"] == "/k.db");
    CHECK(shaped.to_json()["transfer"]["seed"]["digest"] == "ab12");

    // an unseeded transfer block is stored as before seeding existed
    test::write_file(dir / "u.json", R"({"transfer": {"treatment": "mo", "kb": "/k.db"}})");
    const auto plain = runs::EvolveConfig::load(dir / "u.json");
    CHECK(plain.seeding() == nullptr);
    CHECK(plain.run_treatment() == runs::Treatment::mo);
    CHECK(plain.to_json()["transfer"] ==
          nlohmann::json::parse(R"({"treatment": "mo", "kb": "/k.db", "kb_name": ""})"));
}

TEST_CASE("bad transfer.seed settings are refused with the key named", "[runs][config][seed][errors]") {
    test::TempDir dir;
    const std::vector<std::pair<std::string, std::string>> cases = {
        {R"({"transfer": {"seed": {}}})", "c.json: transfer.seed.from is required"},
        {R"({"transfer": {"seed": {"from": "s.db", "count": 0}}})",
         "transfer.seed.count must be >= 1, got 0"},
        {R"({"transfer": {"seed": {"from": "s.db", "count": -4}}})",
         "transfer.seed.count must be >= 1, got -4"},
        {R"({"transfer": {"seed": {"from": "s.db", "with": "elite"}}})", "transfer.seed.with must be one of"},
        {R"({"transfer": {"seed": {"from": "s.db", "size": 3}}})", "transfer.seed.size: unknown key"},
        {R"({"transfer": {"treatment": "seed-mo", "seed": {"from": "s.db"}}})", "with treatment mo"},
    };
    for (const auto& [text, message] : cases) {
        INFO(text);
        test::write_file(dir / "c.json", text);
        CHECK_THROWS_AS(runs::EvolveConfig::load(dir / "c.json"), ConfigError);
        CHECK_THROWS_WITH(runs::EvolveConfig::load(dir / "c.json"), Contains(message));
    }
}
