// stepstone campaign, end to end on tiny campaigns (their statistics are
// tested in tests/runs/campaign_stats_test.cpp).
#include "exp/campaign/campaign.hpp"

#include <algorithm>
#include <catch2/catch.hpp>
#include <chrono>
#include <csignal>
#include <map>
#include <nlohmann/json.hpp>
#include <thread>

#include "db/database.hpp"
#include "db/kb_store.hpp"
#include "kb/oracle.hpp"
#include "support/campaigns.hpp"
#include "support/db_files.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;
using test::finished_digests;
using test::finished_runs;

namespace {

std::string campaign_json(int target_generations, int steps = 200) {
    return test::tiny_campaign_json(target_generations, steps);
}

test::CliResult campaign(const test::TempDir& dir, const std::string& name, const std::vector<std::string>& extra) {
    return test::run_campaign(dir, name, extra);
}

}  // namespace

TEST_CASE("campaign runs every step, and each run equals the same evolve run alone", "[exp][campaign][cli]") {
    test::TempDir dir;
    test::write_file(dir / "c.json", campaign_json(2));
    const auto result = campaign(dir, "camp", {"--jobs", "2"});
    INFO(result.err);
    REQUIRE(result.exit_code == 0);
    CHECK_THAT(result.out, Contains("runs 11") && Contains("finished 11") && Contains("failed 0"));
    const auto camp = dir / "camp";
    for (const char* file : {"campaign.db", "kb/kb.db", "kb/kb-rand.db", "source/seed-4.db", "target/none/seed-1.db",
                             "target/sum/seed-2.db", "target/mo/seed-1.db", "target/sum-rand/seed-2.db",
                             "target/mo-rand/seed-1.db"}) {
        INFO(file);
        CHECK(std::filesystem::exists(camp / file));
    }
    CHECK(finished_digests(camp).size() == 11);

    // the sum run of seed 2, made by hand with the campaign's own KB, is the same run
    const auto alone = test::run_cli({"evolve", "--config", (camp / "config" / "target.json").string(), "--db",
                                      (dir / "alone.db").string(), "--seed", "2", "--generations", "2", "--kb",
                                      (camp / "kb" / "kb.db").string(), "--treatment", "sum", "--quiet"});
    REQUIRE(alone.exit_code == 0);
    CHECK(test::file_digest(dir / "alone.db") == test::file_digest(camp / "target" / "sum" / "seed-2.db"));

    // a second start in the same directory is refused; --resume has nothing left to do
    const auto again = campaign(dir, "camp", {});
    CHECK(again.exit_code == 2);
    CHECK_THAT(again.err, Contains("already holds a campaign") && Contains("--resume"));
    const auto resumed = campaign(dir, "camp", {"--resume"});
    CHECK(resumed.exit_code == 0);
    CHECK_THAT(resumed.out, Contains("already_finished 11"));
}

TEST_CASE("a campaign with kb.delta uses the best source run's KB coarsened to that delta",
          "[exp][campaign][cli][coarsen]") {
    test::TempDir dir;
    auto json = campaign_json(1);
    const std::string from = R"("kb": {"from": "best"})";
    json.replace(json.find(from), from.size(), R"("kb": {"from": "best", "delta": 4})");
    test::write_file(dir / "c.json", json);
    const auto result = campaign(dir, "camp", {"--jobs", "2"});
    INFO(result.err);
    REQUIRE(result.exit_code == 0);
    const auto camp = dir / "camp";
    // the expectation: the source run's stored KB coarsened by the linear-scan KB of
    // tests/kb/oracle.hpp (its segments observed in id order under delta 4, carrying their
    // statistics, as docs/knowledge_base.md describes), not by the library's coarsened().
    // This tiny source run scores nothing, so every cum_reward is 0 and the counts carry the
    // check; kb_cli's kb export --delta test gives the same coarsening rewards that differ
    auto source = db::open_database(camp / "source" / "seed-4.db", db::OpenMode::read_only);
    const auto fine = db::load_kb(source, "run").kb;
    ::kbtest::OracleKb expected;
    expected.dim = fine.params().dim();
    expected.delta = 4.0;
    std::uint64_t fine_count = 0;
    for (std::size_t i = 0; i < fine.size(); ++i) {
        expected.add(fine.segment(i).data(), fine.record(i).cum_reward, fine.record(i).count);
        fine_count += fine.record(i).count;
    }
    auto used = db::open_database(camp / "kb" / "kb.db", db::OpenMode::read_only);
    const auto kb = db::load_kb(used).kb;
    CHECK(kb.params().delta == 4.0);
    CHECK(kb.params().segment_width == fine.params().segment_width);
    REQUIRE(kb.size() == expected.size());
    CHECK(kb.size() < fine.size());  // the larger delta folded segments together
    std::uint64_t count = 0;
    for (std::size_t i = 0; i < kb.size(); ++i) {
        CAPTURE(i);
        const auto segment = kb.segment(i);
        CHECK(std::equal(segment.begin(), segment.end(),
                         expected.values.begin() + static_cast<std::ptrdiff_t>(i * expected.dim)));
        CHECK(kb.record(i).cum_reward == Approx(expected.cum_reward[i]).epsilon(1e-12));
        CHECK(kb.record(i).count == expected.count[i]);
        count += kb.record(i).count;
    }
    CHECK(count == fine_count);  // every observation of the source run is kept, none counted twice
    // the randomized twin is made from the coarse KB: the same segments, each of count 1
    auto rand = db::open_database(camp / "kb" / "kb-rand.db", db::OpenMode::read_only);
    const auto twin = db::load_kb(rand).kb;
    REQUIRE(twin.size() == kb.size());
    CHECK(std::equal(twin.values().begin(), twin.values().end(), kb.values().begin()));
    for (std::size_t i = 0; i < twin.size(); ++i) CHECK(twin.record(i).count == 1);
}

TEST_CASE("a campaign killed mid-way and resumed gives the digests of an uninterrupted one", "[exp][campaign][cli][resume][slow]") {
    test::TempDir dir;
    test::write_file(dir / "c.json", campaign_json(6, 1000));
    REQUIRE(campaign(dir, "whole", {"--jobs", "2"}).exit_code == 0);

    const auto killed = dir / "killed";
    test::run_cli_killed_when({"campaign", (dir / "c.json").string(), "--dir", killed.string(), "--jobs", "1",
                               "--quiet"},
                              [&] { return finished_runs(killed) >= 4; });
    const auto done_before = finished_runs(killed);
    CHECK(done_before >= 4);
    CHECK(done_before < 11);
    std::this_thread::sleep_for(std::chrono::milliseconds(300));  // the orphaned run gets its SIGTERM

    const auto resumed = campaign(dir, "killed", {"--resume", "--jobs", "2"});
    INFO(resumed.err);
    REQUIRE(resumed.exit_code == 0);
    const auto after = finished_digests(killed);
    const auto whole = finished_digests(dir / "whole");
    CHECK(after.size() == 11);
    for (const auto& [id, digest] : whole) {
        INFO("campaign_run " << id << " (" << done_before << " finished before the kill)");
        CHECK(after.count(id) == 1);
        if (after.count(id)) CHECK(after.at(id) == digest);
    }
}

TEST_CASE("bad campaign input: one line, exit 2, nothing started", "[exp][campaign][cli][errors]") {
    test::TempDir dir;
    struct Case {
        std::string json;
        std::string message;
    };
    const std::vector<Case> cases = {
        {R"({"target": {"config": {"task": {"kind": "target"}}, "treatments": ["sum", "best"]}, "kb": {"file": "k.db"}})",
         "target.treatments must be one of none, sum, mo, sum-rand, mo-rand, got \"best\""},
        {R"({"target": {"config": {"task": {"kind": "target"}}, "treatments": ["sum"]}})", "needs kb.file"},
        {R"({"target": {"config": {"task": {"kind": "target"}}}, "kb": {"file": "nowhere.db"}})", "does not exist"},
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
        const auto result = campaign(dir, "camp", {});
        CHECK(result.exit_code == 2);
        CHECK(result.err_lines().size() == 1);
        CHECK_THAT(result.err, Contains(c.message));
        CHECK(!std::filesystem::exists(dir / "camp"));
    }

    // resuming with another config is refused and leaves the campaign as it was
    test::write_file(dir / "c.json", campaign_json(1));
    REQUIRE(campaign(dir, "camp", {}).exit_code == 0);
    const auto before = finished_digests(dir / "camp");
    test::write_file(dir / "c.json", campaign_json(2));
    const auto changed = campaign(dir, "camp", {"--resume"});
    CHECK(changed.exit_code == 2);
    CHECK_THAT(changed.err, Contains("the config differs from the campaign's at target.generations"));
    CHECK(finished_digests(dir / "camp") == before);
}

TEST_CASE("campaign --dry-run prints the plan and its cost without touching the disk", "[exp][campaign][cli]") {
    test::TempDir dir;
    test::write_file(dir / "c.json", campaign_json(2));
    const auto result = test::run_cli({"campaign", (dir / "c.json").string(), "--dry-run"});
    REQUIRE(result.exit_code == 0);
    // 1 source run: (2 + 3) x 8 = 40 evaluations; 10 target runs: (2 + 2) x 8 = 32 each
    CHECK_THAT(result.out, Contains("11 runs, 360 evaluations"));
    // 40 x 200 + 320 x 200 steps (one start each)
    CHECK_THAT(result.out, Contains("at most 7.2e+04 robot steps"));
    // nothing but the config in the directory
    CHECK(std::distance(std::filesystem::directory_iterator(dir.path()), std::filesystem::directory_iterator()) == 1);
}
TEST_CASE("the demo's KB fixture gunzips to a KB with rewards spread over a range, and other data is refused",
          "[exp][campaign][examples]") {
    const std::filesystem::path examples = std::filesystem::path(STEPSTONE_SOURCE_DIR) / "examples";
    // the quick campaign's KB is the shipped fixture: a paper-size source run's KB, coarsened
    const auto quick = runs::CampaignConfig::load(examples / "campaign_quick.json");
    test::TempDir dir;
    exp::gunzip_file(quick.kb_file, dir / "fixture.db");
    auto connection = db::open_database(dir / "fixture.db", db::OpenMode::read_only);
    const auto fixture = db::load_kb(connection);  // validated on load like any KB
    CHECK(fixture.kb.params().channels == 15);
    CHECK(fixture.kb.params().segment_width == 20);
    CHECK(!fixture.randomized_seed);
    CHECK(fixture.kb.max_average() >= 3.0 / 24);  // segments of policies that scored several balls
    REQUIRE(fixture.kb.sources().size() == 1);
    CHECK(fixture.kb.sources()[0].last_generation == 4000);
    CHECK_THROWS_WITH(exp::gunzip_file(examples / "campaign_quick.json", dir / "x.db"),
                      Catch::Contains("campaign_quick.json: not whole gzip data"));
    CHECK_FALSE(std::filesystem::exists(dir / "x.db"));
}

TEST_CASE(
    "SIGTERM stops a campaign cleanly: runs end their generation, nothing is left running, resume equals "
    "whole",
    "[exp][campaign][cli][resume][signals]") {
    test::TempDir dir;
    test::write_file(dir / "c.json", campaign_json(60, 1000));
    REQUIRE(campaign(dir, "whole", {"--jobs", "2"}).exit_code == 0);

    const auto stopped = dir / "stopped";
    double seconds = -1;
    const auto result = test::run_cli_signalled_when(
        {"campaign", (dir / "c.json").string(), "--dir", stopped.string(), "--jobs", "2", "--quiet"},
        [&] { return finished_runs(stopped) >= 2; }, [] {}, SIGTERM, &seconds);
    INFO(result.err);
    CHECK(result.exit_code == 130);
    CHECK(seconds < 10);  // each run ends the generation it is in (~0.05 s here), not the run
    const auto done_before = finished_runs(stopped);
    CHECK(done_before < 11);
    REQUIRE_FALSE(result.err_lines().empty());
    CHECK_THAT(result.err_lines().back(),
               Contains("campaign stopped with " + std::to_string(done_before) + " of 11 runs finished") &&
                   Contains("continue with --resume"));
    {
        auto connection = db::open_database(stopped / "campaign.db", db::OpenMode::read_only);
        CHECK(connection.query_int(
                  "SELECT count(*) FROM campaign_run WHERE status IN ('running', 'failed')") == 0);
    }
    // every file closed as evolve closes it on a stop: no WAL beside any of them
    for (const auto& entry : std::filesystem::recursive_directory_iterator(stopped)) {
        const auto name = entry.path().filename().string();
        INFO(entry.path());
        CHECK_FALSE((name.ends_with("-wal") || name.ends_with("-shm")));
    }
    const auto resumed = campaign(dir, "stopped", {"--resume", "--jobs", "2"});
    INFO(resumed.err);
    REQUIRE(resumed.exit_code == 0);
    CHECK(finished_digests(stopped) == finished_digests(dir / "whole"));
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
    const auto made = campaign(dir, "camp", {});
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
    const auto resumed = campaign(dir, "camp", {"--resume"});
    INFO(resumed.err);
    CHECK(resumed.exit_code == 0);
}
