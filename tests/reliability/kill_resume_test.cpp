// Reliability: evolve runs and campaigns killed with SIGKILL at seeded random
// moments and resumed end identical to uninterrupted ones, every file passing
// PRAGMA integrity_check after each kill; readers during a write never see
// "database is locked" nor a half-written generation.

#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <map>
#include <optional>
#include <random>
#include <thread>

#include "db/database.hpp"
#include "db/digest.hpp"
#include "support/db_files.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;

namespace fs = std::filesystem;

namespace {

// about 20 ms a generation: a kill lands anywhere, creation and commits included
const char* kTinyConfig = R"({
  "task": {"kind": "source", "steps_per_start": 300, "starts": 1},
  "ea": {"population_size": 8, "generations": 25},
  "kb": {"segment_width": 10, "delta": 1.0, "period": 1}
})";

}  // namespace

TEST_CASE("20 evolve runs killed with SIGKILL at seeded random moments resume to the uninterrupted digest",
          "[reliability][slow]") {
    test::TempDir dir;
    test::write_file(dir / "c.json", kTinyConfig);
    // the kill moments are seeded (a failure reproduces) and tied to the run's
    // progress, not to the clock, so they land mid-run on a fast or a loaded
    // machine alike: after generation `after` is committed, plus 0-40 ms
    std::mt19937 draw(20261201);
    std::uniform_int_distribution<int> after_generation(-1, 20);
    std::uniform_int_distribution<int> delay_ms(0, 40);
    std::map<int, std::string> uninterrupted;
    int mid_run = 0;  // kills that left some but not all generations committed
    for (int k = 0; k < 20; ++k) {
        const int seed = 1 + k % 4;
        if (!uninterrupted.count(seed)) {
            const auto full = dir / ("full-" + std::to_string(seed) + ".db");
            REQUIRE(test::run_cli({"evolve", "--config", (dir / "c.json").string(), "--db", full.string(),
                                   "--seed", std::to_string(seed), "--threads", "2", "--quiet"})
                        .exit_code == 0);
            uninterrupted[seed] = test::file_digest(full);
        }
        const auto run = dir / ("run-" + std::to_string(k) + ".db");
        const int after = after_generation(draw);
        const int wait = delay_ms(draw);
        std::optional<std::chrono::steady_clock::time_point> reached;
        test::run_cli_killed_when({"evolve", "--config", (dir / "c.json").string(), "--db", run.string(),
                                   "--seed", std::to_string(seed), "--threads", k % 2 ? "1" : "2", "--quiet"},
                                  [&] {
                                      if (!reached && test::generations_done(run, -2) >= after) {
                                          reached = std::chrono::steady_clock::now();
                                      }
                                      return reached && std::chrono::steady_clock::now() - *reached >=
                                                            std::chrono::milliseconds(wait);
                                  });
        INFO("run " << k << ", killed " << wait << " ms after generation " << after << " was committed");
        const std::string check = test::integrity_check(run);
        CHECK((check == "ok" || check == "absent"));
        if (check == "ok") {
            auto connection = db::open_database(run, db::OpenMode::read_only);
            const auto done = connection.query_int("SELECT generations_done FROM run").value_or(-1);
            mid_run += done >= 0 && done < 25 ? 1 : 0;
        }
        // a killed writer's lock is released with it: the resume is not refused
        std::vector<std::string> resume{"evolve", "--db", run.string(), "--threads", "2", "--quiet"};
        if (check == "absent") {
            resume.insert(resume.end(), {"--config", (dir / "c.json").string(), "--seed", std::to_string(seed)});
        } else {
            resume.emplace_back("--resume");
        }
        auto resumed = test::run_cli(resume);
        INFO(resumed.err);
        REQUIRE(resumed.exit_code == 0);
        CHECK(test::integrity_check(run) == "ok");
        CHECK(test::file_digest(run) == uninterrupted[seed]);
    }
    CHECK(mid_run >= 5);
}

TEST_CASE("readers during a write never see a locked database nor a half-written generation",
          "[reliability][slow]") {
    test::TempDir dir;
    test::write_file(dir / "c.json", R"({
      "task": {"kind": "source", "steps_per_start": 300, "starts": 1},
      "ea": {"population_size": 8, "generations": 150},
      "kb": {"segment_width": 10, "delta": 1.0, "period": 1},
      "seed": 4
    })");
    const auto run = dir / "run.db";
    int reads = 0;
    std::vector<std::string> failures;
    const auto writer = test::run_cli_signalled_when(
        {"evolve", "--config", (dir / "c.json").string(), "--db", run.string(), "--threads", "1", "--quiet"},
        [&] { return fs::exists(run); },
        [&] {
            // read until the writer is done (its lock file goes with it)
            const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
            while (fs::exists(run.string() + ".lock") && std::chrono::steady_clock::now() < deadline) {
                for (const auto& args : std::vector<std::vector<std::string>>{
                         {"db", "info", run.string()},
                         {"kb", "stats", run.string()},
                         {"query", run.string(), "generation_times"},
                         {"query", run.string(), "kb_growth", "--param", "kb_name=run"}}) {
                    const auto result = test::run_cli(args);
                    ++reads;
                    if (result.exit_code != 0) failures.push_back(args[0] + " " + args[1] + ": " + result.err);
                }
                // one transaction per generation: the generations, individuals and checkpoint agree.
                // The four reads share one read transaction (one snapshot); without it the writer
                // may commit a generation between them.
                auto connection = db::open_database(run, db::OpenMode::read_only);
                connection.exec("BEGIN");
                const auto done = connection.query_int("SELECT generations_done FROM run").value_or(-2);
                const auto rows = connection.query_int("SELECT COUNT(*) FROM generation").value_or(-2);
                const auto last = connection.query_int("SELECT MAX(generation) FROM individual").value_or(-1);
                const auto checkpoint = connection.query_int("SELECT generation FROM checkpoint").value_or(-1);
                connection.exec("COMMIT");
                if (rows != done + 1 || last != done || checkpoint != done) {
                    failures.push_back("half-written generation: done " + std::to_string(done) + ", rows " +
                                       std::to_string(rows) + ", individuals up to " + std::to_string(last) +
                                       ", checkpoint " + std::to_string(checkpoint));
                }
            }
        },
        0);
    INFO(writer.err);
    CHECK(writer.exit_code == 0);
    INFO(reads << " reads");
    CHECK(reads >= 8);
    for (const auto& failure : failures) FAIL_CHECK(failure);
    CHECK(failures.empty());
}

TEST_CASE("5 campaigns killed with SIGKILL at seeded random moments resume to the uninterrupted run files",
          "[reliability][slow]") {
    test::TempDir dir;
    test::write_file(dir / "camp.json", R"({
      "source": {"seeds": [1], "config": {
        "task": {"kind": "source", "steps_per_start": 200, "starts": 1},
        "ea": {"population_size": 8, "generations": 6},
        "kb": {"segment_width": 10, "delta": 1.0, "period": 1}}},
      "target": {"seeds": [1, 2], "treatments": ["none", "sum"], "config": {
        "task": {"kind": "target", "steps_per_start": 200, "starts": 1},
        "ea": {"population_size": 8, "generations": 4}}}
    })");
    const std::vector<std::string> files{"source/seed-1.db", "target/none/seed-1.db", "target/sum/seed-1.db",
                                         "target/none/seed-2.db", "target/sum/seed-2.db"};
    REQUIRE(test::run_cli({"campaign", (dir / "camp.json").string(), "--dir", (dir / "full").string(), "--jobs", "2",
                           "--threads", "1", "--quiet"})
                .exit_code == 0);
    std::mt19937 draw(15);
    std::uniform_int_distribution<int> delay_ms(50, 1500);
    for (int k = 0; k < 5; ++k) {
        const auto camp = dir / ("camp-" + std::to_string(k));
        const int wait = delay_ms(draw);
        const auto start = std::chrono::steady_clock::now();
        test::run_cli_killed_when({"campaign", (dir / "camp.json").string(), "--dir", camp.string(), "--jobs", "2",
                                   "--threads", "1", "--quiet"},
                                  [&] {
                                      return std::chrono::steady_clock::now() - start >=
                                             std::chrono::milliseconds(wait);
                                  });
        INFO("campaign " << k << ", killed after " << wait << " ms");
        // the runs die with the campaign (SIGKILL to the children): give them a moment
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
        for (const auto& file : files) {
            const std::string check = test::integrity_check(camp / file);
            INFO(file);
            CHECK((check == "ok" || check == "absent"));
        }
        std::vector<std::string> args{"campaign", (dir / "camp.json").string(), "--dir", camp.string(), "--jobs", "2",
                                      "--threads", "1", "--quiet"};
        if (fs::exists(camp / "campaign.db")) args.emplace_back("--resume");
        auto resumed = test::run_cli(args);
        INFO(resumed.err);
        REQUIRE(resumed.exit_code == 0);
        for (const auto& file : files) {
            INFO(file);
            CHECK(test::file_digest(camp / file) == test::file_digest(dir / "full" / file));
        }
    }

    // killed inside a write to campaign.db: the hot journal left beside it is rolled back by the resume
    const auto index = dir / "full" / "campaign.db";
    const pid_t pid = ::fork();
    REQUIRE(pid >= 0);
    if (pid == 0) {
        db::Connection connection(index, db::OpenMode::read_write);
        // a cache of one page spills the transaction into the file: the journal is then hot
        connection.exec("PRAGMA cache_size = 1; BEGIN IMMEDIATE; UPDATE campaign_run SET wall_time = wall_time + 1");
        for (int k = 0; k < 300; ++k) {
            connection.exec("INSERT INTO meta (key, value) VALUES ('k" + std::to_string(k) + "', printf('%.4000c', 'x'))");
        }
        ::raise(SIGKILL);
    }
    int status = 0;
    ::waitpid(pid, &status, 0);
    REQUIRE(fs::exists(index.string() + "-journal"));
    const auto hot = test::run_cli({"stats", (dir / "full").string()});  // a reader cannot roll it back: it says what to do
    CHECK(hot.exit_code == 1);
    CHECK_THAT(hot.err, Contains("left mid-write by a killed program"));
    auto resumed = test::run_cli({"campaign", (dir / "camp.json").string(), "--dir", (dir / "full").string(),
                                  "--resume", "--quiet"});
    INFO(resumed.err);
    CHECK(resumed.exit_code == 0);
    CHECK_FALSE(fs::exists(index.string() + "-journal"));
}

namespace {

// runs the binary to a successful end and returns its peak resident set size in KiB
long peak_rss_kib(const std::vector<std::string>& args) {
    const auto result = test::run_cli(args);
    INFO(result.err);
    REQUIRE(result.exit_code == 0);
    return result.peak_rss_kib;
}

}  // namespace

TEST_CASE("evolve's resident memory stays flat over ten times the generations", "[reliability][slow][memory]") {
    test::TempDir dir;
    // no KB: its growth is the one memory that should grow with the run. Generations are cheap
    // (4 policies, 50 steps) so that SQLite's page cache (2 MB at most) is full at the short
    // run's end: it fills over the first ~100 generations, then stays.
    test::write_file(dir / "c.json", R"({
      "task": {"kind": "source", "steps_per_start": 50, "starts": 1},
      "ea": {"population_size": 4, "generations": 10},
      "seed": 2
    })");
    const auto run = [&](const std::string& name, int generations) {
        return peak_rss_kib({"evolve", "--config", (dir / "c.json").string(), "--db", (dir / name).string(),
                             "--generations", std::to_string(generations), "--threads", "1", "--quiet"});
    };
    const long short_run = run("short.db", 200);
    const long long_run = run("long.db", 2000);
    INFO("peak RSS: " << short_run << " KiB at 200 generations, " << long_run << " KiB at 2000");
    CHECK(static_cast<double>(long_run) < 1.10 * static_cast<double>(short_run));
}
