// evolve --mpi and campaign --mpi under a real mpirun. The oracle is the same
// command without MPI: a run's digest, a campaign's run digests.
#include <signal.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <map>
#include <thread>

#include "db/database.hpp"
#include "db/digest.hpp"
#include "exp/campaign/campaign_kb.hpp"
#include "support/campaigns.hpp"
#include "support/db_files.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;
using Catch::Matchers::StartsWith;
namespace fs = std::filesystem;

namespace {

// a source run that observes its KB every generation
const char* kSource = R"({"task": {"kind": "source", "steps_per_start": 200, "starts": 1},
  "ea": {"population_size": 8, "generations": 4},
  "kb": {"segment_width": 20, "delta": 1.83, "period": 1}})";

// one source run, its KB, 5 treatments x 2 seeds (the tiny campaign of tests/exp)
std::string campaign_json(int target_generations) {
    return R"({
  "source": {"config": {"task": {"kind": "source", "steps_per_start": 200, "starts": 1},
      "ea": {"population_size": 8}, "kb": {"segment_width": 20, "delta": 1.83, "period": 1}},
    "seeds": [4], "generations": 3},
  "kb": {"from": "best"},
  "randomize_seed": 9,
  "target": {"config": {"task": {"kind": "target", "steps_per_start": 200, "starts": 1}, "ea": {"population_size": 8}},
    "runs": 2, "generations": )" +
           std::to_string(target_generations) + "}}";
}

std::string digest_of(const fs::path& run) {
    auto connection = db::open_database(run, db::OpenMode::read_only);
    return db::run_digest(connection);
}

// the pid of MPI rank `rank` of the job whose command line holds `marker`, 0 if none
pid_t rank_pid(int rank, const std::string& marker) {
    for (const auto& entry : fs::directory_iterator("/proc")) {
        const std::string name = entry.path().filename();
        if (name.find_first_not_of("0123456789") != std::string::npos) continue;
        std::string cmdline = test::read_file(entry.path() / "cmdline");
        std::replace(cmdline.begin(), cmdline.end(), '\0', ' ');
        if (cmdline.find(marker) == std::string::npos || cmdline.find("mpirun") != std::string::npos)
            continue;
        std::string environ = test::read_file(entry.path() / "environ");
        std::replace(environ.begin(), environ.end(), '\0', '\n');
        if (("\n" + environ).find("\nOMPI_COMM_WORLD_RANK=" + std::to_string(rank) + "\n") !=
            std::string::npos) {
            return static_cast<pid_t>(std::stoi(name));
        }
    }
    return 0;
}

// `args` under mpirun on `ranks` ranks, rank `victim_rank` killed with SIGKILL once `ready()`
// holds; `victim` receives its pid (0: not found)
// the run file (under `dir`) that process `pid` has open, empty if none
std::string open_run_file(pid_t pid, const fs::path& dir) {
    std::error_code error;
    for (const auto& fd : fs::directory_iterator(fs::path("/proc") / std::to_string(pid) / "fd", error)) {
        const std::string target = fs::read_symlink(fd.path(), error).string();
        if (target.rfind(dir.string() + "/target/", 0) == 0 && target.size() > 3 &&
            target.compare(target.size() - 3, 3, ".db") == 0) {
            return target;
        }
    }
    return "";
}

// `args` under mpirun on `ranks` ranks; rank `victim_rank` (found by `marker` in its command line)
// is killed with SIGKILL once `ready(its pid)` holds; `victim` receives its pid
test::CliResult run_and_kill_rank(int ranks, const std::vector<std::string>& args, int victim_rank,
                                  const std::string& marker, const std::function<bool(pid_t)>& ready,
                                  pid_t& victim) {
    return test::run_program_signalled_when(
        test::mpirun_command(ranks, args),
        [&] {
            victim = rank_pid(victim_rank, marker);
            return victim > 0 && ready(victim);
        },
        [&] { ::kill(victim, SIGKILL); }, 0);
}

}  // namespace

TEST_CASE("evolve --mpi with 2 and 3 ranks gives the single-process digest, KB lookups included",
          "[mpi][evolve]") {
    test::TempDir dir;
    test::write_file(dir / "source.json", kSource);
    const auto source = [&](const std::string& db) {
        return std::vector<std::string>{
            "evolve", "--config", (dir / "source.json").string(), "--db", (dir / db).string(), "--seed",
            "3",      "--quiet"};
    };
    REQUIRE(test::run_cli(source("one.db")).exit_code == 0);
    for (int ranks : {2, 3}) {
        auto args = source("ranks-" + std::to_string(ranks) + ".db");
        args.emplace_back("--mpi");
        const auto result = test::run_program(test::mpirun_command(ranks, args));
        INFO(ranks << " ranks: " << result.err);
        REQUIRE(result.exit_code == 0);
        CHECK_THAT(result.out, Contains("generations 4"));
        CHECK(digest_of(dir / ("ranks-" + std::to_string(ranks) + ".db")) == digest_of(dir / "one.db"));
    }

    // a target run shaped by the demo's KB (the tiny source run's KB has no reward, so every r_max
    // would be 0): the ranks compute r_max, on chunks of up to 10 policies stepped in lanes (64
    // policies in generation 0 shared out in sixths)
    exp::gunzip_file(fs::path(STEPSTONE_SOURCE_DIR) / "examples/fixtures/demo_kb.db.gz", dir / "kb.db");
    test::write_file(dir / "target.json", R"({"task": {"kind": "target", "steps_per_start": 200, "starts": 1},
      "ea": {"population_size": 32, "generations": 3}})");
    const std::vector<std::string> target{"evolve",
                                          "--config",
                                          (dir / "target.json").string(),
                                          "--seed",
                                          "5",
                                          "--kb",
                                          (dir / "kb.db").string(),
                                          "--treatment",
                                          "mo",
                                          "--quiet",
                                          "--db"};
    auto alone = target;
    alone.push_back((dir / "mo-1.db").string());
    REQUIRE(test::run_cli(alone).exit_code == 0);
    auto spread = target;
    spread.push_back((dir / "mo-3.db").string());
    spread.emplace_back("--mpi");
    const auto result = test::run_program(test::mpirun_command(3, spread));
    INFO(result.err);
    REQUIRE(result.exit_code == 0);
    CHECK(digest_of(dir / "mo-3.db") == digest_of(dir / "mo-1.db"));
    // the digest covers r_max: most of these policies match the KB
    auto run = db::open_database(dir / "mo-1.db", db::OpenMode::read_only);
    CHECK(run.query_int("SELECT count(*) FROM individual WHERE r_max > 0") > 80);
}

TEST_CASE(
    "evolve --mpi with a rank whose math library rounds otherwise: one line naming the rank, no generation",
    "[mpi][evolve][errors][determinism]") {
    __builtin_cpu_init();
    if (!(__builtin_cpu_supports("fma") && __builtin_cpu_supports("avx2"))) {
        WARN("this CPU lacks FMA or AVX2: glibc has no other build to give rank 1");
        return;
    }
    test::TempDir dir;
    std::string libm = kSource;  // the machine's own math: what a mixed job must refuse
    libm.insert(libm.rfind('}'), R"(, "math": "libm")");
    test::write_file(dir / "source.json", libm);
    const std::vector<std::string> args{"evolve",
                                        "--config",
                                        (dir / "source.json").string(),
                                        "--db",
                                        (dir / "run.db").string(),
                                        "--seed",
                                        "3",
                                        "--quiet",
                                        "--mpi"};
    // rank 0 as this machine runs it, rank 1 as a machine without FMA and AVX2 would (glibc's plain
    // builds, stepstone's generic kernels)
    std::vector<std::string> command{"mpirun", "--allow-run-as-root", "--oversubscribe", "-np",
                                     "1",      STEPSTONE_BINARY};
    command.insert(command.end(), args.begin(), args.end());
    for (const std::string part :
         {":", "-np", "1", "/usr/bin/env", "GLIBC_TUNABLES=glibc.cpu.hwcaps=-AVX2,-FMA",
          "STEPSTONE_NO_AVX2=1", STEPSTONE_BINARY})
        command.push_back(part);
    command.insert(command.end(), args.begin(), args.end());
    const auto result = test::run_program(command);
    INFO(result.err);
    CHECK(result.exit_code != 0);
    CHECK_THAT(result.err, Contains("rank 1") && Contains("math library rounds differently from rank 0's"));
    CHECK(test::generations_done(dir / "run.db") < 0);  // no generation committed (or no file)

    // with "math": "portable" the library does not matter: the mixed job runs, to the single-process digest
    std::string portable = kSource;
    portable.insert(portable.rfind('}'), R"(, "math": "portable")");
    test::write_file(dir / "source.json", portable);
    fs::remove(dir / "run.db");
    const auto mixed = test::run_program(command);
    INFO(mixed.err);
    REQUIRE(mixed.exit_code == 0);
    REQUIRE(test::run_cli({"evolve", "--config", (dir / "source.json").string(), "--db",
                           (dir / "one.db").string(), "--seed", "3", "--quiet"})
                .exit_code == 0);
    CHECK(digest_of(dir / "run.db") == digest_of(dir / "one.db"));
}

TEST_CASE("evolve --mpi with chunks of tens of genomes each way: no rank waits on another's send",
          "[mpi][evolve]") {
    // population 200: rank 0 has two chunks of 100 and 75 genomes (tens of kB) out to rank 1 while
    // rank 1 answers the first (kB of results); sends that waited to be received would hold both
    test::TempDir dir;
    test::write_file(dir / "wide.json", R"({"task": {"kind": "source", "steps_per_start": 100, "starts": 1},
      "ea": {"population_size": 200, "generations": 1}})");
    const auto args = [&](const std::string& db) {
        return std::vector<std::string>{
            "evolve", "--config", (dir / "wide.json").string(), "--db", (dir / db).string(), "--seed",
            "2",      "--quiet"};
    };
    REQUIRE(test::run_cli(args("one.db")).exit_code == 0);
    auto spread = args("two.db");
    spread.emplace_back("--mpi");
    // half a second when it works; a job whose ranks hold each other ends with timeout's 124
    std::vector<std::string> bounded{"timeout", "60"};
    for (auto& word : test::mpirun_command(2, spread)) bounded.push_back(word);
    const auto result = test::run_program(bounded);
    INFO(result.err);
    REQUIRE(result.exit_code == 0);
    CHECK(digest_of(dir / "two.db") == digest_of(dir / "one.db"));
}

TEST_CASE("campaign --mpi with 3 ranks gives the run digests of the single-process campaign",
          "[mpi][campaign]") {
    test::TempDir dir;
    test::write_file(dir / "c.json", campaign_json(2));
    const auto one =
        test::run_cli({"campaign", (dir / "c.json").string(), "--dir", (dir / "one").string(), "--quiet"});
    REQUIRE(one.exit_code == 0);
    const auto result = test::run_program(test::mpirun_command(
        3, {"campaign", (dir / "c.json").string(), "--dir", (dir / "three").string(), "--quiet", "--mpi"}));
    INFO(result.err);
    REQUIRE(result.exit_code == 0);
    CHECK_THAT(result.out, Contains("finished 11") && Contains("failed 0"));
    const auto expected = test::finished_digests(dir / "one");
    CHECK(expected.size() == 11);
    CHECK(test::finished_digests(dir / "three") == expected);
    CHECK(fs::exists(dir / "three" / "kb" / "kb-rand.db"));
}

TEST_CASE("a rank killed mid-campaign: one line naming it and its run, then --resume on 2 ranks ends equal",
          "[mpi][campaign][resume]") {
    test::TempDir dir;
    test::write_file(dir / "c.json", campaign_json(30));
    const auto killed = dir / "killed";
    pid_t victim = 0;
    std::string running;  // the run file rank 1 had open when killed
    const auto result = run_and_kill_rank(
        3, {"campaign", (dir / "c.json").string(), "--dir", killed.string(), "--quiet", "--mpi"}, 1,
        killed.string(),
        [&](pid_t pid) {
            // killed while it writes a target run (not between two runs)
            if (test::finished_runs(killed) < 3) return false;
            running = open_run_file(pid, killed);
            return !running.empty();
        },
        victim);
    REQUIRE(victim > 0);
    INFO(result.err);
    CHECK(result.exit_code != 0);
    const auto done_before = test::finished_runs_after_exit(killed);
    CHECK(done_before < 11);
    // rank 0's line: the rank, its pid and the run it had
    CHECK_THAT(result.err,
               Contains("stepstone: error: campaign stopped: rank 1 (pid " + std::to_string(victim)) &&
                   Contains("died while running " + running + ";") && Contains("continue with --resume"));

    const auto resumed =
        test::run_program(test::mpirun_command(2, {"campaign", (dir / "c.json").string(), "--dir",
                                                   killed.string(), "--quiet", "--mpi", "--resume"}));
    INFO(resumed.err);
    REQUIRE(resumed.exit_code == 0);
    const auto whole =
        test::run_cli({"campaign", (dir / "c.json").string(), "--dir", (dir / "whole").string(), "--quiet"});
    REQUIRE(whole.exit_code == 0);
    INFO(done_before << " runs finished before the kill");
    CHECK(test::finished_digests(killed) == test::finished_digests(dir / "whole"));
    CHECK(test::finished_digests(killed).size() == 11);
}

TEST_CASE(
    "a rank killed mid-run of evolve --mpi: one line, the file at a committed generation, resume ends equal",
    "[mpi][evolve][resume]") {
    test::TempDir dir;
    std::string config = kSource;
    config.replace(config.find("\"generations\": 4"), 16, "\"generations\": 60");
    test::write_file(dir / "long.json", config);
    const auto run = dir / "run.db";
    REQUIRE(test::run_cli({"evolve", "--config", (dir / "long.json").string(), "--db",
                           (dir / "whole.db").string(), "--seed", "2", "--quiet"})
                .exit_code == 0);
    pid_t victim = 0;
    const auto ready = [&](pid_t) {
        if (!fs::exists(run)) return false;
        try {
            auto connection = db::open_database(run, db::OpenMode::read_only);
            return connection.query_int("SELECT count(*) FROM generation").value_or(0) >= 3;
        } catch (const std::exception&) {
            return false;
        }
    };
    const auto result = run_and_kill_rank(3,
                                          {"evolve", "--config", (dir / "long.json").string(), "--db",
                                           run.string(), "--seed", "2", "--quiet", "--mpi"},
                                          2, run.string(), ready, victim);
    REQUIRE(victim > 0);
    INFO(result.err);
    CHECK(result.exit_code != 0);
    CHECK_THAT(result.err,
               Contains("stepstone: error: " + run.string() + ": rank 2 (pid " + std::to_string(victim)) &&
                   Contains("died; stopped after generation") && Contains("continue with --resume"));
    const auto resumed = test::run_program(
        test::mpirun_command(2, {"evolve", "--db", run.string(), "--resume", "--quiet", "--mpi"}));
    INFO(resumed.err);
    REQUIRE(resumed.exit_code == 0);
    CHECK(digest_of(run) == digest_of(dir / "whole.db"));
}

TEST_CASE("bad input under mpirun: rank 0's one error line, the other ranks let go, nothing written",
          "[mpi][errors]") {
    test::TempDir dir;
    test::write_file(dir / "bad.json", R"({"ea": {"population_size": 10}})");
    const auto result = test::run_program(test::mpirun_command(
        2, {"evolve", "--config", (dir / "bad.json").string(), "--db", (dir / "run.db").string(), "--mpi"}));
    CHECK(result.exit_code == 2);
    CHECK_THAT(result.err, Contains("stepstone: error: ") && Contains("population_size"));
    CHECK_FALSE(fs::exists(dir / "run.db"));
    const auto jobs = test::run_program(test::mpirun_command(
        2, {"campaign", (dir / "bad.json").string(), "--dir", (dir / "c").string(), "--mpi", "--jobs", "2"}));
    CHECK(jobs.exit_code == 2);
    CHECK_THAT(jobs.err, Contains("--jobs does not apply with --mpi"));
}

TEST_CASE("bench mpi times evolve --mpi on 2 ranks against 2 threads in one process", "[mpi][bench]") {
    // the case starts mpirun itself: CI runs as root on few cores
    ::setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
    ::setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
    ::setenv("OMPI_MCA_rmaps_base_oversubscribe", "1", 1);
    const auto result = test::run_cli({"bench", "mpi", "--quick", "--csv"});
    INFO(result.err);
    REQUIRE(result.exit_code == 0);
    CHECK_THAT(result.out,
               StartsWith("case,baseline_per_s,candidate_per_s,ratio,ratio_min,ratio_max,rounds\nmpi,"));
    const auto list = test::run_cli({"bench", "--list"});
    CHECK_THAT(list.out, Contains("2 MPI ranks (pml ob1) vs 1 process on 2 threads"));
}

TEST_CASE("campaign --mpi: a run that fails on its rank is recorded with its error, the others finish",
          "[mpi][campaign][errors]") {
    test::TempDir dir;
    test::write_file(dir / "c.json", campaign_json(2));
    const auto camp = dir / "camp";
    const std::vector<std::string> args{
        "campaign", (dir / "c.json").string(), "--dir", camp.string(), "--quiet", "--mpi"};
    REQUIRE(test::run_program(test::mpirun_command(2, args)).exit_code == 0);
    // one run file replaced by garbage: its rank's resume fails on it, as a child process would
    test::write_file(camp / "target" / "sum" / "seed-2.db", std::string(4096, 'x'));
    auto resume = args;
    resume.emplace_back("--resume");
    const auto result = test::run_program(test::mpirun_command(3, resume));
    INFO(result.err);
    CHECK(result.exit_code != 0);
    CHECK_THAT(result.out, Contains("finished 10") && Contains("failed 1"));
    CHECK_THAT(result.err, Contains("campaign: failed: target/sum/seed-2.db: ") &&
                               Contains("1 run(s) failed (logs in " + (camp / "logs").string()));
    CHECK_THAT(test::read_file(camp / "logs" / "target-sum-seed-2.log"), Contains("stepstone: error: "));
    CHECK(test::finished_digests(camp).size() == 10);
}

TEST_CASE("evolve --mpi of a seeded, shaped target run gives the single-process digest",
          "[mpi][evolve][seeding]") {
    test::TempDir dir;
    test::write_file(dir / "source.json", kSource);
    REQUIRE(test::run_cli({"evolve", "--config", (dir / "source.json").string(), "--db",
                           (dir / "source.db").string(), "--seed", "3", "--quiet"})
                .exit_code == 0);
    exp::gunzip_file(fs::path(STEPSTONE_SOURCE_DIR) / "examples/fixtures/demo_kb.db.gz", dir / "kb.db");
    test::write_file(dir / "target.json", R"({"task": {"kind": "target", "steps_per_start": 200, "starts": 1},
      "ea": {"population_size": 8, "generations": 3}})");
    const auto seeded = [&](const std::string& db) {
        return std::vector<std::string>{"evolve",
                                        "--config",
                                        (dir / "target.json").string(),
                                        "--seed",
                                        "6",
                                        "--seed-from",
                                        (dir / "source.db").string(),
                                        "--seed-with",
                                        "best",
                                        "--seed-count",
                                        "5",
                                        "--kb",
                                        (dir / "kb.db").string(),
                                        "--treatment",
                                        "sum",
                                        "--quiet",
                                        "--db",
                                        (dir / db).string()};
    };
    REQUIRE(test::run_cli(seeded("one.db")).exit_code == 0);
    auto spread = seeded("two.db");
    spread.emplace_back("--mpi");
    const auto result = test::run_program(test::mpirun_command(2, spread));
    INFO(result.err);
    REQUIRE(result.exit_code == 0);
    CHECK(digest_of(dir / "two.db") == digest_of(dir / "one.db"));
    // generation 0 holds the seeds: its first individuals are the source's stored genomes
    auto run = db::open_database(dir / "two.db", db::OpenMode::read_only);
    CHECK(run.query_int("SELECT count(*) FROM genome WHERE individual_id < 5") == 5);
    auto treatment = run.prepare("SELECT treatment FROM run");
    REQUIRE(treatment.step());
    CHECK(treatment.column_text(0) == "seed-sum");
}
