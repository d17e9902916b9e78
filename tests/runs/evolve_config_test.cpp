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
