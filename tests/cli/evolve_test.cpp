#include <algorithm>
#include <catch2/catch.hpp>
#include <chrono>
#include <thread>

#include "db/database.hpp"
#include "db/digest.hpp"
#include "support/db_files.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;

namespace {

// long enough (about 0.1 s a generation) to be killed in the middle
const char* kConfig = R"({
  "task": {"kind": "source", "steps_per_start": 2000, "starts": 3},
  "ea": {"population_size": 16, "generations": 30},
  "seed": 5
})";

}  // namespace

TEST_CASE("evolve killed with SIGKILL mid-run resumes to the digest of an uninterrupted run",
          "[cli][evolve][resume][slow]") {
    test::TempDir dir;
    test::write_file(dir / "c.json", kConfig);
    const auto killed = dir / "killed.db";

    // wait until a few generations are committed, then kill without warning
    test::run_cli_killed_when({"evolve", "--config", (dir / "c.json").string(), "--db", killed.string(),
                               "--threads", "2", "--quiet"},
                              [&] { return test::generations_done(killed) >= 3; });
    const int done_at_kill = test::generations_done(killed);
    INFO("generations committed when killed: " << done_at_kill);
    CHECK(done_at_kill >= 3);
    CHECK(done_at_kill < 30);

    auto resumed = test::run_cli({"evolve", "--config", (dir / "c.json").string(), "--db", killed.string(),
                                  "--resume", "--threads", "1", "--quiet"});
    REQUIRE(resumed.exit_code == 0);
    auto full = test::run_cli({"evolve", "--config", (dir / "c.json").string(), "--db",
                               (dir / "full.db").string(), "--threads", "2", "--quiet"});
    REQUIRE(full.exit_code == 0);
    CHECK(test::file_digest(killed) == test::file_digest(dir / "full.db"));

    auto digest_cli = test::run_cli({"db", "digest", killed.string()});
    CHECK(digest_cli.exit_code == 0);
    CHECK(digest_cli.out == test::file_digest(killed) + "\n");

    auto replay = test::run_cli(
        {"replay", killed.string(), "--individual", "best", "--csv", (dir / "best.csv").string()});
    CHECK(replay.exit_code == 0);
    CHECK_THAT(replay.out, Contains("stored_reward"));
    // one CSV row per step run, after the header
    const std::string csv = test::read_file(dir / "best.csv");
    const auto lines = std::count(csv.begin(), csv.end(), '\n');
    const auto steps_at = replay.out.find("steps ");
    REQUIRE(steps_at != std::string::npos);
    CHECK(lines == 1 + std::stol(replay.out.substr(steps_at + 6)));
    CHECK(csv.rfind("start,step,x,y,heading", 0) == 0);
    // an existing CSV is refused without --force and left as it was
    auto again = test::run_cli({"replay", killed.string(), "--csv", (dir / "best.csv").string()});
    CHECK(again.exit_code == 2);
    CHECK(test::read_file(dir / "best.csv") == csv);
}

TEST_CASE("evolve usage and config errors exit 2 with one line and no file", "[cli][evolve][errors]") {
    test::TempDir dir;
    test::write_file(dir / "bad.json", R"({"ea": {"population_size": 6}})");
    auto result =
        test::run_cli({"evolve", "--config", (dir / "bad.json").string(), "--db", (dir / "r.db").string()});
    CHECK(result.exit_code == 2);
    REQUIRE(result.err_lines().size() == 1);
    CHECK_THAT(result.err, Contains("bad.json: ea.population_size must be a multiple of 4, got 6"));
    CHECK(!std::filesystem::exists(dir / "r.db"));

    result = test::run_cli({"evolve", "--config", (dir / "bad.json").string()});
    CHECK(result.exit_code == 2);
    CHECK(result.err_lines().size() == 1);

    result = test::run_cli({"replay", (dir / "absent.db").string()});
    CHECK(result.exit_code == 1);
    CHECK(result.err_lines().size() == 1);
}
