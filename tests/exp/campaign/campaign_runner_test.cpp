// How a campaign carries out its runs (lib/exp/campaign/campaign_runner.cpp):
// killed with SIGKILL or stopped with SIGTERM mid-way, then resumed, it gives
// the run digests of an uninterrupted campaign.
#include "exp/campaign/campaign_runner.hpp"

#include <catch2/catch.hpp>
#include <chrono>
#include <csignal>
#include <thread>

#include "db/database.hpp"
#include "support/campaigns.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;

TEST_CASE("a campaign killed mid-way and resumed gives the digests of an uninterrupted one",
          "[exp][campaign][cli][resume][slow]") {
    test::TempDir dir;
    test::write_file(dir / "c.json", test::tiny_campaign_json(6, 1000));
    REQUIRE(test::run_campaign(dir, "whole", {"--jobs", "2"}).exit_code == 0);

    const auto killed = dir / "killed";
    test::run_cli_killed_when(
        {"campaign", (dir / "c.json").string(), "--dir", killed.string(), "--jobs", "1", "--quiet"},
        [&] { return test::finished_runs(killed) >= 4; });
    const auto done_before = test::finished_runs_after_exit(killed);
    CHECK(done_before >= 4);
    CHECK(done_before < 11);
    std::this_thread::sleep_for(std::chrono::milliseconds(300));  // the orphaned run gets its SIGTERM

    const auto resumed = test::run_campaign(dir, "killed", {"--resume", "--jobs", "2"});
    INFO(resumed.err);
    REQUIRE(resumed.exit_code == 0);
    const auto after = test::finished_digests(killed);
    const auto whole = test::finished_digests(dir / "whole");
    CHECK(after.size() == 11);
    for (const auto& [id, digest] : whole) {
        INFO("campaign_run " << id << " (" << done_before << " finished before the kill)");
        CHECK(after.count(id) == 1);
        if (after.count(id)) CHECK(after.at(id) == digest);
    }
}

TEST_CASE(
    "SIGTERM stops a campaign cleanly: runs end their generation, nothing is left running, resume equals "
    "whole",
    "[exp][campaign][cli][resume][signals]") {
    test::TempDir dir;
    test::write_file(dir / "c.json", test::tiny_campaign_json(20, 1000));
    REQUIRE(test::run_campaign(dir, "whole", {"--jobs", "2"}).exit_code == 0);

    const auto stopped = dir / "stopped";
    double seconds = -1;
    const auto result = test::run_cli_signalled_when(
        {"campaign", (dir / "c.json").string(), "--dir", stopped.string(), "--jobs", "2", "--quiet"},
        [&] { return test::finished_runs(stopped) >= 2; }, [] {}, SIGTERM, &seconds);
    INFO(result.err);
    CHECK(result.exit_code == 130);
    CHECK(seconds < 10);  // each run ends the generation it is in (~0.05 s here), not the run
    const auto done_before = test::finished_runs_after_exit(stopped);
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
    const auto resumed = test::run_campaign(dir, "stopped", {"--resume", "--jobs", "2"});
    INFO(resumed.err);
    REQUIRE(resumed.exit_code == 0);
    CHECK(test::finished_digests(stopped) == test::finished_digests(dir / "whole"));
}
