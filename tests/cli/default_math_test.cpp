// Portable math is the default of new runs and campaigns (0.2.0); files made with
// libm, whose stored configs carry no "math" key, keep libm when resumed, replayed or
// resumed with a config that names no math.

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <string>

#include "db/database.hpp"
#include "support/campaigns.hpp"
#include "support/db_files.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;

namespace {

const std::string kBody = R"({"task": {"kind": "source", "steps_per_start": 300, "starts": 1},
  "ea": {"population_size": 8, "generations": 3}, "seed": 5)";

std::string stored_math(const std::filesystem::path& run) {
    auto connection = db::open_database(run, db::OpenMode::read_only);
    auto row = connection.prepare("SELECT coalesce(json_extract(config, '$.math'), '(absent)') FROM run");
    return row.step() ? row.column_text(0) : "";
}

// the same run config three ways: naming no math, libm, portable
void write_configs(const test::TempDir& dir) {
    test::write_file(dir / "default.json", kBody + "}");
    test::write_file(dir / "libm.json", kBody + R"(, "math": "libm"})");
    test::write_file(dir / "portable.json", kBody + R"(, "math": "portable"})");
}

test::CliResult evolve(const std::filesystem::path& config, const std::filesystem::path& db,
                       std::vector<std::string> extra = {}) {
    std::vector<std::string> args{"evolve", "--config", config.string(), "--db", db.string(), "--quiet"};
    args.insert(args.end(), extra.begin(), extra.end());
    return test::run_cli(args);
}

}  // namespace

TEST_CASE("a new run is portable unless its config pins libm, which is stored as older files store it",
          "[cli][determinism]") {
    test::TempDir dir;
    write_configs(dir);
    for (const char* name : {"default", "libm", "portable"})
        REQUIRE(evolve(dir / (std::string(name) + ".json"), dir / (std::string(name) + ".db")).exit_code ==
                0);
    CHECK(stored_math(dir / "default.db") == "portable");
    CHECK(stored_math(dir / "libm.db") == "(absent)");  // as every run file before 0.2.0
    const auto digest = [&](const char* name) {
        return test::file_digest(dir / (std::string(name) + ".db"));
    };
    CHECK(digest("default") == digest("portable"));
    CHECK(digest("default") != digest("libm"));
}

TEST_CASE("a libm run resumes as libm with a config that names no math, and refuses one that names portable",
          "[cli][determinism][resume]") {
    test::TempDir dir;
    write_configs(dir);
    REQUIRE(evolve(dir / "libm.json", dir / "whole.db", {"--generations", "4"}).exit_code == 0);
    REQUIRE(evolve(dir / "libm.json", dir / "part.db", {"--generations", "2"}).exit_code == 0);
    // the user's config names no math: the run's own (libm) is kept, to the uninterrupted digest
    const auto resumed = evolve(dir / "default.json", dir / "part.db", {"--resume", "--generations", "4"});
    INFO(resumed.err);
    REQUIRE(resumed.exit_code == 0);
    CHECK(test::file_digest(dir / "part.db") == test::file_digest(dir / "whole.db"));
    CHECK(stored_math(dir / "part.db") == "(absent)");
    // a config that names the other math is a config change
    const auto other = evolve(dir / "portable.json", dir / "part.db", {"--resume", "--generations", "5"});
    CHECK(other.exit_code != 0);
    CHECK_THAT(other.err, Contains("math"));
    CHECK(test::generations_done(dir / "part.db") == 4);
    // replay reads the stored config's math: the stored rewards come back
    const auto replay = test::run_cli({"replay", (dir / "part.db").string()});
    INFO(replay.out << replay.err);
    CHECK(replay.exit_code == 0);
}

TEST_CASE("a campaign made with libm resumes as libm from a config that names no math", "[cli][campaign]") {
    test::TempDir dir;
    auto json = nlohmann::json::parse(test::tiny_campaign_json(1));
    json["source"]["config"]["math"] = "libm";
    json["target"]["config"]["math"] = "libm";
    test::write_file(dir / "c.json", json.dump());
    REQUIRE(test::run_campaign(dir, "camp", {}).exit_code == 0);
    const auto before = test::finished_digests(dir / "camp");
    // the same campaign, its config no longer naming the math: resumed (nothing to do), not refused
    json["source"]["config"].erase("math");
    json["target"]["config"].erase("math");
    test::write_file(dir / "c.json", json.dump());
    const auto resumed = test::run_campaign(dir, "camp", {"--resume"});
    INFO(resumed.err);
    CHECK(resumed.exit_code == 0);
    CHECK(test::finished_digests(dir / "camp") == before);
    // the step configs the runs read name libm
    const auto target = nlohmann::json::parse(test::read_file(dir / "camp" / "config" / "target.json"));
    CHECK(target["math"] == "libm");
    // naming portable is a change of config
    json["target"]["config"]["math"] = "portable";
    test::write_file(dir / "c.json", json.dump());
    const auto changed = test::run_campaign(dir, "camp", {"--resume"});
    CHECK(changed.exit_code != 0);
    CHECK_THAT(changed.err, Contains("math"));
}
