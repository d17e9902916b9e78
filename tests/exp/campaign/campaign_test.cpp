// stepstone campaign, end to end on tiny campaigns (lib/exp/campaign/campaign.cpp):
// every step run, each run equal to the same evolve run alone, the refusals
// of bad input and of a changed config, kb.file as given.
#include "exp/campaign/campaign.hpp"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "db/database.hpp"
#include "support/campaigns.hpp"
#include "support/db_files.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;

TEST_CASE("campaign runs every step, and each run equals the same evolve run alone", "[exp][campaign][cli]") {
    test::TempDir dir;
    test::write_file(dir / "c.json", test::tiny_campaign_json(2));
    const auto result = test::run_campaign(dir, "camp", {"--jobs", "2"});
    INFO(result.err);
    REQUIRE(result.exit_code == 0);
    CHECK_THAT(result.out, Contains("runs 11") && Contains("finished 11") && Contains("failed 0"));
    const auto camp = dir / "camp";
    for (const char* file : {"campaign.db", "kb/kb.db", "kb/kb-rand.db", "source/seed-4.db",
                             "target/none/seed-1.db", "target/sum/seed-2.db", "target/mo/seed-1.db",
                             "target/sum-rand/seed-2.db", "target/mo-rand/seed-1.db"}) {
        INFO(file);
        CHECK(std::filesystem::exists(camp / file));
    }
    CHECK(test::finished_digests(camp).size() == 11);

    // the sum run of seed 2, made by hand with the campaign's own KB, is the same run
    const auto alone =
        test::run_cli({"evolve", "--config", (camp / "config" / "target.json").string(), "--db",
                       (dir / "alone.db").string(), "--seed", "2", "--generations", "2", "--kb",
                       (camp / "kb" / "kb.db").string(), "--treatment", "sum", "--quiet"});
    REQUIRE(alone.exit_code == 0);
    CHECK(test::file_digest(dir / "alone.db") == test::file_digest(camp / "target" / "sum" / "seed-2.db"));

    // a second start in the same directory is refused; --resume has nothing left to do
    const auto again = test::run_campaign(dir, "camp", {});
    CHECK(again.exit_code == 2);
    CHECK_THAT(again.err, Contains("already holds a campaign") && Contains("--resume"));
    const auto resumed = test::run_campaign(dir, "camp", {"--resume"});
    CHECK(resumed.exit_code == 0);
    CHECK_THAT(resumed.out, Contains("already_finished 11"));
}

TEST_CASE("bad campaign input: one line, exit 2, nothing started", "[exp][campaign][cli][errors]") {
    test::TempDir dir;
    struct Case {
        std::string json;
        std::string message;
    };
    const std::vector<Case> cases = {
        {R"({"target": {"config": {"task": {"kind": "target"}}, "treatments": ["sum", "best"]}, "kb": {"file": "k.db"}})",
         "target.treatments must be one of none, sum, mo, sum-rand, mo-rand, seed, seed-sum, seed-mo, "
         "seed-sum-rand, seed-mo-rand, got \"best\""},
        {R"({"target": {"config": {"task": {"kind": "target"}}, "treatments": ["sum"]}})", "needs kb.file"},
        {R"({"target": {"config": {"task": {"kind": "target"}}}, "kb": {"file": "nowhere.db"}})",
         "does not exist"},
        {R"({"source": {"config": {"task": {"kind": "source"}}}, "target": {"config": {"task": {"kind": "target"}}}})",
         "source.config has no kb block"},
        {R"({"target": {"config": {"task": {"kind": "target"}}, "treatments": ["none"], "seeds": [1, 1]}})",
         "target.seeds repeats a seed"},
        {R"({"target": {"config": "missing.json", "treatments": ["none"]}})", "missing.json"},
        {R"({"target": {"config": {"task": {"kind": "target"}}, "treatments": ["none"], "gens": 3}})",
         "target.gens: unknown key"},
    };
    for (const auto& c : cases) {
        INFO(c.json);
        test::write_file(dir / "c.json", c.json);
        const auto result = test::run_campaign(dir, "camp", {});
        CHECK(result.exit_code == 2);
        CHECK(result.err_lines().size() == 1);
        CHECK_THAT(result.err, Contains(c.message));
        CHECK(!std::filesystem::exists(dir / "camp"));
    }

    // resuming with another config is refused and leaves the campaign as it was
    test::write_file(dir / "c.json", test::tiny_campaign_json(1));
    REQUIRE(test::run_campaign(dir, "camp", {}).exit_code == 0);
    const auto before = test::finished_digests(dir / "camp");
    test::write_file(dir / "c.json", test::tiny_campaign_json(2));
    const auto changed = test::run_campaign(dir, "camp", {"--resume"});
    CHECK(changed.exit_code == 2);
    CHECK_THAT(changed.err, Contains("the config differs from the campaign's at target.generations"));
    CHECK(test::finished_digests(dir / "camp") == before);
}

TEST_CASE("a campaign keeps kb.file as its config gives it, and resumes one that stored the absolute path",
          "[exp][campaign][cli][kb]") {
    test::TempDir dir;
    const auto fixture = std::filesystem::path(STEPSTONE_SOURCE_DIR) / "examples/fixtures/demo_kb.db.gz";
    const std::string given = std::filesystem::relative(fixture, dir.path()).string();
    REQUIRE(given.rfind("..", 0) == 0);  // a relative path, from the config's folder
    test::write_file(
        dir / "c.json",
        R"({"kb": {"file": ")" + given +
            R"("}, "target": {"config": {"task": {"kind": "target", "steps_per_start": 100, "starts": 1}, "ea": {"population_size": 8}}, "runs": 1, "generations": 1, "treatments": ["sum"]}})");
    const auto made = test::run_campaign(dir, "camp", {});
    INFO(made.err);
    REQUIRE(made.exit_code == 0);
    const auto text_of = [&](const std::string& sql) {
        auto connection = db::open_database(dir / "camp" / "campaign.db", db::OpenMode::read_only);
        auto row = connection.prepare(sql);
        REQUIRE(row.step());
        return row.column_text(0);
    };
    const auto stored_config = [&] { return nlohmann::json::parse(text_of("SELECT config FROM campaign")); };
    CHECK(stored_config()["kb"]["file"] == given);
    CHECK(text_of("SELECT made_from FROM campaign_kb WHERE name = 'kb'") == "copy of " + given);
    // a campaign made before: its campaign.db holds the absolute path of the same file
    {
        auto connection = db::open_database(dir / "camp" / "campaign.db", db::OpenMode::read_write);
        auto config = stored_config();
        config["kb"]["file"] = std::filesystem::weakly_canonical(fixture).string();
        auto update = connection.prepare("UPDATE campaign SET config = :config");
        update.bind(":config", config.dump()).step();
    }
    const auto resumed = test::run_campaign(dir, "camp", {"--resume"});
    INFO(resumed.err);
    CHECK(resumed.exit_code == 0);
}
