// CampaignConfig parsing and plan_runs, in process: the expectations come from
// docs/transfer.md's table of keys and its plan (seed-major target runs), and
// the example campaigns' designs from docs/results.md.
#include "runs/campaign_config.hpp"

#include <catch2/catch.hpp>

#include "core/error.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;

namespace {

const char* kTask = R"("task": {"kind": "target", "steps_per_start": 100, "starts": 1})";

nlohmann::json parse(const std::string& text) { return nlohmann::json::parse(text); }

runs::CampaignConfig from(const std::string& text) {
    return runs::CampaignConfig::from_json(parse(text), "c.json", std::filesystem::current_path());
}

std::string target(const std::string& extra) {
    return std::string(R"({"target": {"config": {)") + kTask + R"(}, )" + extra + "}}";
}

std::string error_of(const std::string& text) {
    try {
        from(text);
    } catch (const ConfigError& e) {
        return e.what();
    }
    return "no error";
}

}  // namespace

TEST_CASE("campaign config: runs N with first_seed S gives seeds S to S + N - 1",
          "[runs][campaign][config]") {
    const auto config = from(target(R"("runs": 3, "first_seed": 5, "treatments": ["none"])"));
    CHECK(config.target.seeds == std::vector<std::uint64_t>{5, 6, 7});
    CHECK_FALSE(config.source.has_value());
    CHECK(from(target(R"("treatments": ["none"])")).target.seeds == std::vector<std::uint64_t>{1});
    CHECK(from(target(R"("seeds": [9, 2], "treatments": ["none"])")).target.seeds ==
          std::vector<std::uint64_t>{9, 2});
}

TEST_CASE("campaign config: the default treatments are all five in the paper's order",
          "[runs][campaign][config]") {
    test::TempDir dir;
    test::write_file(dir / "kb.db", "");  // kb.file must exist; it is not read by the parse
    const auto config = runs::CampaignConfig::from_json(
        parse(std::string(R"({"kb": {"file": "kb.db"}, "target": {"config": {)") + kTask + "}}}"), "c.json",
        dir.path());
    REQUIRE(config.treatments.size() == 5);
    CHECK(runs::to_string(config.treatments[0]) == std::string("none"));
    CHECK(runs::to_string(config.treatments[1]) == std::string("sum"));
    CHECK(runs::to_string(config.treatments[2]) == std::string("mo"));
    CHECK(runs::to_string(config.treatments[3]) == std::string("sum-rand"));
    CHECK(runs::to_string(config.treatments[4]) == std::string("mo-rand"));
    CHECK(config.kb_from == runs::KbFrom::file);
    CHECK(config.kb_file == dir / "kb.db");
    // stored and shown as the config gives it, not as this machine's absolute path
    CHECK(config.kb_file_given == "kb.db");
    CHECK(config.to_json()["kb"]["file"] == "kb.db");
    CHECK(config.randomize_seed == 1);
    CHECK(config.needs_kb());
    CHECK(config.needs_randomized_kb());
}

TEST_CASE("campaign config: bad keys and values are refused naming the key",
          "[runs][campaign][config][errors]") {
    CHECK_THAT(error_of(target(R"("seeds": [1], "runs": 2)")),
               Contains("c.json") && Contains("target.seeds"));
    CHECK_THAT(error_of(target(R"("seeds": [1, 1], "treatments": ["none"])")), Contains("repeats a seed"));
    CHECK_THAT(error_of(target(R"("seeds": [], "treatments": ["none"])")), Contains("non-empty array"));
    CHECK_THAT(error_of(target(R"("treatments": ["none", "none"])")), Contains("names none twice"));
    CHECK_THAT(error_of(target(R"("treatments": ["sum"])")), Contains("needs kb.file"));
    CHECK_THAT(error_of(R"({"kb": {"from": "best"}})"), Contains("target is required"));
    CHECK_THAT(error_of(target(R"("treatments": ["none"], "colour": 1)")), Contains("colour"));
    CHECK_THAT(error_of(R"({"kb": {"from": "best", "file": "x.db"}, )" +
                        target(R"("treatments": ["none"])").substr(1)),
               Contains("cannot both be given"));
}

TEST_CASE("campaign plan: source runs by seed, then target runs seed-major in config order",
          "[runs][campaign][config]") {
    const auto config =
        from(std::string(R"({"source": {"config": {)") + kTask +
             R"(, "kb": {"segment_width": 20, "delta": 1.0}}, "seeds": [4, 2], "generations": 3},
        "target": {"config": {)" +
             kTask + R"(}, "runs": 2, "generations": 5, "treatments": ["mo", "none"]}})");
    const auto plan = runs::plan_runs(config);
    const std::vector<std::string> files{"source/seed-4.db",    "source/seed-2.db",
                                         "target/mo/seed-1.db", "target/none/seed-1.db",
                                         "target/mo/seed-2.db", "target/none/seed-2.db"};
    REQUIRE(plan.size() == files.size());
    for (std::size_t k = 0; k < plan.size(); ++k) {
        INFO(k);
        CHECK(plan[k].file == files[k]);
        CHECK(plan[k].step == (k < 2 ? runs::CampaignStep::source : runs::CampaignStep::target));
        CHECK(plan[k].generations == (k < 2 ? 3 : 5));
    }
    CHECK(plan[0].seed == 4);
    CHECK(plan[4].seed == 2);
    CHECK(runs::to_string(plan[4].treatment) == std::string("mo"));
    CHECK(runs::to_string(plan[0].treatment) == std::string("none"));
    // the stored form parses back to the same plan
    const auto again =
        runs::CampaignConfig::from_json(config.to_json(), "stored", std::filesystem::current_path());
    CHECK(again.to_json() == config.to_json());
    CHECK(runs::plan_runs(again).size() == plan.size());
}

TEST_CASE("every example campaign parses, and the replication one and the quick one carry their design",
          "[runs][campaign][config][examples]") {
    const std::filesystem::path examples = std::filesystem::path(STEPSTONE_SOURCE_DIR) / "examples";
    int parsed = 0;
    for (const auto& entry : std::filesystem::directory_iterator(examples)) {
        const auto name = entry.path().filename().string();
        if (name.rfind("campaign_", 0) != 0 || entry.path().extension() != ".json") continue;
        INFO(name);
        CHECK_NOTHROW(runs::CampaignConfig::load(entry.path()));
        ++parsed;
    }
    CHECK(parsed >= 3);
    const auto replication = runs::CampaignConfig::load(examples / "campaign_replication.json");
    REQUIRE(replication.source);
    CHECK(replication.source->config.ea.population_size == 200);  // the paper's source run
    CHECK(replication.source->generations == 4000);
    CHECK(replication.treatments.size() == 5);
    CHECK(replication.target.config.task.starts == 3);

    // the quick campaign's KB is the shipped fixture (tests/exp/campaign/campaign_kb_test.cpp loads it)
    const auto quick = runs::CampaignConfig::load(examples / "campaign_quick.json");
    REQUIRE(quick.kb_from == runs::KbFrom::file);
    CHECK(quick.kb_file.extension() == ".gz");
    CHECK(std::filesystem::file_size(quick.kb_file) < (1u << 20));  // committed: under 1 MiB
}

TEST_CASE("campaign config: seeded treatments and the seed block", "[runs][campaign][config][seed]") {
    test::TempDir dir;
    const std::string source =
        std::string(R"("source": {"config": {)") + kTask + R"(, "kb": {"segment_width": 20, "delta": 1.0}}})";
    const auto make = [&](const std::string& extra, const std::string& treatments) {
        return runs::CampaignConfig::from_json(parse("{" + source + extra + R"(, "target": {"config": {)" +
                                                     kTask + R"(}, "treatments": )" + treatments + "}}"),
                                               "c.json", dir.path());
    };
    // seeded treatments without a seed block: the best source run's population
    const auto config = make("", R"(["none", "seed", "seed-sum"])");
    REQUIRE(config.seed.has_value());
    CHECK_FALSE(config.seed->from_file);
    CHECK(config.seed->with == runs::SeedWith::population);
    CHECK_FALSE(config.seed->count.has_value());
    CHECK(config.seeded());
    CHECK(config.needs_kb());  // seed-sum shapes
    CHECK_FALSE(config.needs_randomized_kb());
    CHECK(config.to_json()["seed"] == parse(R"({"from": "best", "with": "population"})"));
    const auto plan = runs::plan_runs(config);
    REQUIRE(plan.size() == 4);
    CHECK(plan[2].file == "target/seed/seed-1.db");
    CHECK(plan[3].file == "target/seed-sum/seed-1.db");
    CHECK(plan[3].treatment == runs::Treatment::seed_sum);
    // a seed alone needs no KB
    CHECK_FALSE(make("", R"(["seed"])").needs_kb());
    // a campaign without seeded treatments stores no seed block (older campaigns resume unchanged)
    CHECK_FALSE(make("", R"(["none"])").to_json().contains("seed"));

    // a given run file, as given; with and count
    test::write_file(dir / "src.db", "");
    const auto file = make(R"(, "seed": {"file": "src.db", "with": "best", "count": 3})", R"(["seed-mo"])");
    CHECK(file.seed->from_file);
    CHECK(file.seed->file == dir / "src.db");
    CHECK(file.seed->count == 3);
    CHECK(file.to_json()["seed"] == parse(R"({"file": "src.db", "with": "best", "count": 3})"));
    const auto again = runs::CampaignConfig::from_json(file.to_json(), "stored", dir.path());
    CHECK(again.to_json() == file.to_json());

    const auto error = [&](const std::string& extra, const std::string& treatments) {
        try {
            make(extra, treatments);
        } catch (const ConfigError& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    CHECK_THAT(error(R"(, "seed": {"file": "none.db"})", R"(["seed"])"),
               Contains("seed.file: none.db does not exist"));
    CHECK_THAT(error(R"(, "seed": {"from": "best", "file": "src.db"})", R"(["seed"])"),
               Contains("cannot both be given"));
    CHECK_THAT(error(R"(, "seed": {"from": "worst"})", R"(["seed"])"), Contains("seed.from"));
    CHECK_THAT(error(R"(, "seed": {"count": 0})", R"(["seed"])"), Contains("seed.count must be >= 1, got 0"));
    CHECK_THAT(error(R"(, "seed": {"with": "all"})", R"(["seed"])"), Contains("seed.with"));
    CHECK_THAT(error_of(target(R"("treatments": ["seed"])")),
               Contains("a seeded treatment needs a source step"));
    CHECK_THAT(error_of(std::string(R"({"source": {"config": {)") + kTask +
                        R"(, "ea": {"population_size": 12}}}, "target": {"config": {)" + kTask +
                        R"(}, "treatments": ["seed"]}})"),
               Contains("seed.with population needs one population size"));
}
