// Where an output goes when its path is not a plain new file: "-" is standard
// output; a symbolic link is followed (the link stays, the file it names gets the
// output); a FIFO or a character device is written through, never replaced; a
// database is never written to standard output, a FIFO or a device. The FIFOs,
// links and device nodes are made in a temporary folder; no real /dev entry is
// written.

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <future>
#include <sstream>
#include <string>

#include "exp/campaign/campaign_kb.hpp"
#include "support/kb_fixtures.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {

// the commands that write a CSV, each with its output option last
std::vector<std::vector<std::string>> csv_writers(const fs::path& run) {
    return {
        {"replay", run.string(), "--csv"},
        {"simulate", "--steps", "30", "--starts", "1", "--csv"},
        {"export", run.string(), "--what", "generations", "--csv"},
        {"pool", "--runs", (run.parent_path() / "runs.csv").string(), "--events",
         (run.parent_path() / "events.csv").string(), "--runs-csv"},
    };
}

// a runs and an events CSV for pool, beside `run`
void write_pool_inputs(const fs::path& run) {
    test::write_file(run.parent_path() / "runs.csv",
                     "treatment,seed,generation,best_reward,success,policies,ball_policies,mean_r_max\n"
                     "none,1,10,0.25,0,100,0,\n");
    test::write_file(run.parent_path() / "events.csv",
                     "treatment,seed,event,generation,observed\nnone,1,press,2,1\nnone,1,pickup,10,0\n"
                     "none,1,release,10,0\nnone,1,ball,10,0\n");
}

std::string read_fifo(const fs::path& fifo) {
    const int fd = ::open(fifo.c_str(), O_RDONLY);
    std::string text;
    char buffer[4096];
    for (ssize_t n; (n = ::read(fd, buffer, sizeof buffer)) > 0;)
        text.append(buffer, static_cast<std::size_t>(n));
    ::close(fd);
    return text;
}

}  // namespace

TEST_CASE("'-' writes a CSV to standard output, for every command that writes one", "[cli][outputs]") {
    test::TempDir dir;
    kbtest::make_run(dir / "run.db");
    write_pool_inputs(dir / "run.db");
    for (auto args : csv_writers(dir / "run.db")) {
        CAPTURE(args[0]);
        auto to_file = args;
        to_file.push_back((dir / (args[0] + ".csv")).string());
        const auto file = test::run_cli(to_file);
        REQUIRE(file.exit_code == 0);
        args.push_back("-");
        const auto out = test::run_cli(args, dir.path());
        INFO(out.err);
        REQUIRE(out.exit_code == 0);
        CHECK_THAT(out.out, Contains(test::read_file(dir / (args[0] + ".csv"))));
        CHECK_FALSE(fs::exists(dir / "-"));  // not a file named "-"
    }
}

TEST_CASE("a link is followed and kept, and without --force its existing file is kept too",
          "[cli][outputs]") {
    test::TempDir dir;
    kbtest::make_run(dir / "run.db");
    fs::create_directory(dir / "real");
    test::write_file(dir / "real" / "out.csv", "old\n");
    fs::create_symlink("real/out.csv", dir / "link.csv");
    const auto refused =
        test::run_cli({"replay", (dir / "run.db").string(), "--csv", (dir / "link.csv").string()});
    CHECK(refused.exit_code != 0);
    CHECK(refused.err_lines().size() == 1);
    CHECK_THAT(refused.err, Contains("already exists"));
    CHECK(test::read_file(dir / "real" / "out.csv") == "old\n");
    const auto forced =
        test::run_cli({"replay", (dir / "run.db").string(), "--csv", (dir / "link.csv").string(), "--force"});
    REQUIRE(forced.exit_code == 0);
    CHECK(fs::is_symlink(dir / "link.csv"));
    CHECK(fs::read_symlink(dir / "link.csv") == "real/out.csv");
    CHECK_THAT(test::read_file(dir / "real" / "out.csv"), Contains("step"));
    // a database output through a link: the link stays and names the new KB file
    fs::create_symlink("real/kb.db", dir / "kb-link.db");
    REQUIRE(test::run_cli({"kb", "export", (dir / "run.db").string(), "--out", (dir / "kb-link.db").string()})
                .exit_code == 0);
    CHECK(fs::is_symlink(dir / "kb-link.db"));
    CHECK(fs::is_regular_file(dir / "real" / "kb.db"));
}

TEST_CASE("a FIFO is written through and stays a FIFO, with or without --force", "[cli][outputs]") {
    test::TempDir dir;
    kbtest::make_run(dir / "run.db");
    const auto expected = [&] {
        REQUIRE(test::run_cli({"replay", (dir / "run.db").string(), "--csv", (dir / "plain.csv").string()})
                    .exit_code == 0);
        return test::read_file(dir / "plain.csv");
    }();
    REQUIRE(::mkfifo((dir / "pipe").c_str(), 0600) == 0);
    for (const bool force : {false, true}) {
        auto reader = std::async(std::launch::async, [&] { return read_fifo(dir / "pipe"); });
        std::vector<std::string> args{"replay", (dir / "run.db").string(), "--csv", (dir / "pipe").string()};
        if (force) args.push_back("--force");
        const auto result = test::run_cli(args);
        INFO(result.err);
        CHECK(result.exit_code == 0);
        CHECK(reader.get() == expected);
        struct stat st {};
        REQUIRE(::lstat((dir / "pipe").c_str(), &st) == 0);
        CHECK(S_ISFIFO(st.st_mode));
    }
    // a database is not written into a FIFO: one line, nothing replaced
    const auto db = test::run_cli(
        {"kb", "export", (dir / "run.db").string(), "--out", (dir / "pipe").string(), "--force"});
    CHECK(db.exit_code != 0);
    CHECK(db.err_lines().size() == 1);
    CHECK_THAT(db.err, Contains("FIFO or a device"));
    struct stat st {};
    REQUIRE(::lstat((dir / "pipe").c_str(), &st) == 0);
    CHECK(S_ISFIFO(st.st_mode));
    const auto stdout_db = test::run_cli({"kb", "export", (dir / "run.db").string(), "--out", "-"});
    CHECK(stdout_db.exit_code != 0);
    CHECK_THAT(stdout_db.err, Contains("standard output"));
}

TEST_CASE("device nodes are written through, never replaced: a full one fails in one line",
          "[cli][outputs]") {
    test::TempDir dir;
    kbtest::make_run(dir / "run.db");
    // twins of /dev/null (1, 3) and /dev/full (1, 7) inside the temporary folder
    if (::mknod((dir / "null").c_str(), S_IFCHR | 0600, makedev(1, 3)) != 0 ||
        ::mknod((dir / "full").c_str(), S_IFCHR | 0600, makedev(1, 7)) != 0) {
        WARN("mknod is not permitted here: the device-node case is skipped");
        return;
    }
    for (const bool force : {false, true}) {
        std::vector<std::string> to_null{"replay", (dir / "run.db").string(), "--csv",
                                         (dir / "null").string()};
        std::vector<std::string> to_full{"replay", (dir / "run.db").string(), "--csv",
                                         (dir / "full").string()};
        if (force) {
            to_null.push_back("--force");
            to_full.push_back("--force");
        }
        CHECK(test::run_cli(to_null).exit_code == 0);
        const auto full = test::run_cli(to_full);
        CHECK(full.exit_code != 0);
        CHECK(full.err_lines().size() == 1);
        CHECK_THAT(full.err, Contains("write failed"));
        for (const char* node : {"null", "full"}) {
            struct stat st {};
            REQUIRE(::lstat((dir / node).c_str(), &st) == 0);
            CHECK(S_ISCHR(st.st_mode));
        }
    }
}

TEST_CASE("whole-number options refuse negative, fractional, exponent and out-of-range text in one line",
          "[cli][errors]") {
    test::TempDir dir;
    kbtest::make_run(dir / "run.db");
    REQUIRE(test::run_cli({"kb", "export", (dir / "run.db").string(), "--out", (dir / "kb.db").string()})
                .exit_code == 0);
    const auto refused = [&](std::vector<std::string> args, const std::string& message) {
        CAPTURE(args);
        const auto result = test::run_cli(args);
        CHECK(result.exit_code == 2);
        CHECK(result.err_lines().size() == 1);
        CHECK_THAT(result.err, Contains(message));
    };
    const auto randomize = [&](const std::string& seed) {
        return std::vector<std::string>{
            "kb", "randomize", (dir / "kb.db").string(), "--out", (dir / "rand.db").string(), "--seed", seed};
    };
    refused(randomize("-4"), ">= 0, got -4");                          // CLI11 stored 2^64 - 4
    refused(randomize("1e23"), "whole number in digits, got '1e23'");  // CLI11 stored 2^64 - 1
    refused(randomize("18446744073709551616"), "out of range");        // 2^64
    refused(randomize("2.5"), "whole number in digits");
    CHECK_FALSE(fs::exists(dir / "rand.db"));
    refused({"evolve", "--config", "x.json", "--db", (dir / "e.db").string(), "--generations", "1e3"},
            "--generations");
    refused({"kb", "calibrate", (dir / "run.db").string(), "--segment-width", "-10"}, ">= 0, got -10");
    // the largest seed still goes through
    CHECK(test::run_cli(randomize("18446744073709551615")).exit_code == 0);
}

TEST_CASE("an option given twice is one line in the project's words, not CLI11's", "[cli][errors]") {
    const auto result =
        test::run_cli({"kb", "randomize", "a.db", "--out", "b.db", "--seed", "1", "--seed", "2"});
    CHECK(result.exit_code == 2);
    CHECK(result.err_lines().size() == 1);
    CHECK_THAT(result.err, Contains("--seed: given 2 times; give it once"));
    CHECK_THAT(result.err, !Contains("At Most"));
}

TEST_CASE("CLI11's own wordings come out in the project's, one line each", "[cli][errors]") {
    const auto said = [](std::vector<std::string> args, const std::string& message, const std::string& raw) {
        CAPTURE(args);
        const auto result = test::run_cli(args);
        CHECK(result.exit_code == 2);
        CHECK(result.err_lines().size() == 1);
        CHECK_THAT(result.err, Contains(message));
        CHECK_THAT(result.err, !Contains(raw));
    };
    said({"stats", "camp", "--threshold", "abc"}, "--threshold: 'abc' is not a value of its kind",
         "Could not convert");
    said({"pool", "--runs"}, "--runs: needs a value after it", "required TEXT missing");
    said({"kb", "calibrate", "run.db", "--reading", "strides"},
         "--reading must be one of segments|windows, got 'strides'", "not in {");
    said({"evolve", "--config", "c.json", "--db", ""}, "--db is empty", "cannot move");
}

TEST_CASE("the README's transfer example shapes for real: the demo KB gives policies an r_max",
          "[cli][docs]") {
    // README, "Transfer": the shipped demo KB, its randomized twin, and a sum run of
    // target_quick.json (here 1 generation of 200 steps, in a temporary folder)
    test::TempDir dir;
    const fs::path examples = fs::path(STEPSTONE_SOURCE_DIR) / "examples";
    exp::gunzip_file(examples / "fixtures" / "demo_kb.db.gz", dir / "demo_kb.db");
    REQUIRE(test::run_cli({"kb", "randomize", (dir / "demo_kb.db").string(), "--out",
                           (dir / "kb-rand.db").string(), "--seed", "1"})
                .exit_code == 0);
    const auto run = test::run_cli({"evolve", "--config", (examples / "target_quick.json").string(), "--db",
                                    (dir / "sum.db").string(), "--kb", (dir / "demo_kb.db").string(),
                                    "--treatment", "sum", "--seed", "1", "--generations", "1", "--quiet"});
    INFO(run.err);
    REQUIRE(run.exit_code == 0);
    CHECK_THAT(run.err, !Contains("largest average reward is 0"));  // the warning a quick source KB gives
    const auto exported =
        test::run_cli({"export", (dir / "sum.db").string(), "--what", "individuals", "--csv", "-"});
    REQUIRE(exported.exit_code == 0);
    // some policy's r_max (the `r_max` column) is above 0
    const auto split = [](const std::string& line) {
        std::vector<std::string> fields;
        std::istringstream in(line);
        for (std::string field; std::getline(in, field, ',');) fields.push_back(field);
        return fields;
    };
    std::istringstream rows(exported.out);
    std::string line;
    std::getline(rows, line);
    const auto header = split(line);
    const auto column = std::find(header.begin(), header.end(), "r_max") - header.begin();
    REQUIRE(static_cast<std::size_t>(column) < header.size());
    bool positive = false;
    while (std::getline(rows, line)) {
        const auto fields = split(line);
        const auto k = static_cast<std::size_t>(column);
        if (k < fields.size() && !fields[k].empty() && std::stod(fields[k]) > 0) positive = true;
    }
    CHECK(positive);
}
