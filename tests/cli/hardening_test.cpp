// The rough edges of issue 15, each seen by running the real binary as a new
// user would: one writer per run file, Ctrl-C that says how to resume, paths
// named as the user gave them, and usage errors instead of internal ones.

#include <catch2/catch.hpp>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "db/database.hpp"
#include "db/digest.hpp"
#include "support/db_files.hpp"
#include "support/kb_fixtures.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;
using Catch::Matchers::StartsWith;

namespace fs = std::filesystem;

namespace {

// about 0.1 s a generation on one core: long enough to act while it runs
const char* kSlowConfig = R"({
  "task": {"kind": "source", "steps_per_start": 2000, "starts": 3},
  "ea": {"population_size": 16, "generations": 40},
  "seed": 5
})";

const char* kTinyConfig = R"({
  "task": {"kind": "source", "steps_per_start": 200, "starts": 1},
  "ea": {"population_size": 8, "generations": 2},
  "seed": 3
})";

const char* kTinyTargetConfig = R"({
  "task": {"kind": "target", "steps_per_start": 200, "starts": 1},
  "ea": {"population_size": 8, "generations": 1},
  "seed": 3
})";

// exit `code`, exactly one stderr line "stepstone: error: ..." holding `needle`, nothing on stdout
void check_refused(const test::CliResult& result, int code, const std::string& needle) {
    INFO(result.err);
    CHECK(result.exit_code == code);
    REQUIRE(result.err_lines().size() == 1);
    CHECK_THAT(result.err_lines()[0], StartsWith("stepstone: error: "));
    CHECK_THAT(result.err_lines()[0], Contains(needle));
    CHECK(result.out.empty());
}

}  // namespace

TEST_CASE(
    "a second writer on a run file is refused at once, naming the first, Ctrl-C stops cleanly and says how "
    "to resume, and --resume without --config continues to the uninterrupted digest",
    "[cli][harden][lock][interrupt]") {
    test::TempDir dir;
    test::write_file(dir / "c.json", kSlowConfig);
    const auto run = dir / "run.db";
    const std::vector<std::string> args{"evolve", "--config", (dir / "c.json").string(), "--db", run.string(),
                                        "--threads", "1", "--quiet"};
    test::CliResult second, migrate;
    double seconds = 0;
    const auto first = test::run_cli_signalled_when(
        args, [&] { return test::generations_done(run) >= 2; },
        [&] {
            auto resume = args;
            resume.push_back("--resume");
            second = test::run_cli(resume);
            migrate = test::run_cli({"db", "migrate", run.string()});  // another writer
        },
        SIGINT, &seconds);

    // the second writer: refused before touching anything, naming the first process
    check_refused(second, 1, run.string() + ": another process is writing it (pid ");
    CHECK_THAT(second.err, Contains("evolve"));
    check_refused(migrate, 1, run.string() + ": another process is writing it (pid ");

    // the first: stopped at a generation boundary, within about a second, with how to resume
    INFO(first.err);
    CHECK(first.exit_code == 130);
    REQUIRE(first.err_lines().size() == 1);
    CHECK_THAT(first.err_lines()[0], StartsWith("stepstone: interrupted: " + run.string()));
    CHECK_THAT(first.err_lines()[0], Contains("continue with --resume"));
    CHECK_THAT(first.err_lines()[0], Contains("(stepstone evolve --db " + run.string() + " --resume)"));
    CHECK(seconds < 1.5);
    // every committed generation is in the main file: nothing beside it
    CHECK_FALSE(fs::exists(run.string() + "-wal"));
    CHECK_FALSE(fs::exists(run.string() + "-shm"));
    CHECK_FALSE(fs::exists(run.string() + ".lock"));
    const int done = test::generations_done(run);
    CHECK(done >= 2);
    CHECK(done < 40);

    // rerunning without --resume points to --resume, and leaves the run alone
    const std::string before = test::read_file(run);
    check_refused(test::run_cli(args), 2, "continue it with --resume");
    CHECK(test::read_file(run) == before);

    // --resume alone reads the stored config, and ends where an uninterrupted run does
    auto resumed = test::run_cli({"evolve", "--db", run.string(), "--resume", "--threads", "2", "--quiet"});
    INFO(resumed.err);
    REQUIRE(resumed.exit_code == 0);
    auto full = test::run_cli({"evolve", "--config", (dir / "c.json").string(), "--db", (dir / "full.db").string(),
                               "--threads", "2", "--quiet"});
    REQUIRE(full.exit_code == 0);
    CHECK(test::file_digest(run) == test::file_digest(dir / "full.db"));
}

TEST_CASE("SIGTERM stops evolve like Ctrl-C", "[cli][harden][interrupt]") {
    test::TempDir dir;
    test::write_file(dir / "c.json", kSlowConfig);
    const auto run = dir / "run.db";
    double seconds = 0;
    const auto result = test::run_cli_signalled_when(
        {"evolve", "--config", (dir / "c.json").string(), "--db", run.string(), "--threads", "1", "--quiet"},
        [&] { return test::generations_done(run) >= 1; }, nullptr, SIGTERM, &seconds);
    CHECK(result.exit_code == 130);
    CHECK_THAT(result.err, Contains("--resume"));
    CHECK(seconds < 1.5);
    CHECK_FALSE(fs::exists(run.string() + "-wal"));
    CHECK(test::generations_done(run) >= 1);
}

TEST_CASE("a file given as --dir is a usage error (exit 2), not an internal one, and is left unchanged",
          "[cli][harden][errors]") {
    test::TempDir dir;
    test::write_file(dir / "file", "not a folder");
    test::write_file(dir / "camp.json", R"({"target": {"config": {"task": {"kind": "target"}}}})");
    check_refused(test::run_cli({"demo", "--dir", (dir / "file").string(), "--examples",
                                 std::string(STEPSTONE_SOURCE_DIR) + "/examples", "--quiet"}),
                  2, (dir / "file").string() + ": exists and is not a directory");
    check_refused(
        test::run_cli({"campaign", std::string(STEPSTONE_SOURCE_DIR) + "/examples/campaign_quick.json", "--dir",
                       (dir / "file").string(), "--quiet"}),
        2, (dir / "file").string() + ": exists and is not a directory");
    CHECK(test::read_file(dir / "file") == "not a folder");
}

TEST_CASE("errors name the user's path in full, never a temporary file or the last component",
          "[cli][harden][errors]") {
    test::TempDir dir;
    test::write_file(dir / "c.json", kTinyConfig);
    auto result = test::run_cli({"evolve", "--config", (dir / "c.json").string(), "--db", "/no/such/dir/x.db"});
    check_refused(result, 2, "/no/such/dir/x.db: cannot create: /no/such/dir does not exist");
    CHECK_THAT(result.err, !Contains(".tmp-"));

    REQUIRE(test::run_cli({"evolve", "--config", (dir / "c.json").string(), "--db", (dir / "run.db").string(),
                           "--quiet"})
                .exit_code == 0);
    result = test::run_cli({"kb", "export", (dir / "run.db").string(), "--out", "/no/such/dir/k.db"});
    check_refused(result, 2, "/no/such/dir/k.db");
    CHECK_THAT(result.err, !Contains(".tmp-"));

    // a database error names the path as given, folder included
    check_refused(test::run_cli({"db", "info", (dir / "absent.db").string()}), 1,
                  (dir / "absent.db").string() + ": no such file");
    test::make_foreign_sqlite(dir / "foreign.db");
    check_refused(test::run_cli({"db", "info", (dir / "foreign.db").string()}), 1,
                  (dir / "foreign.db").string() + ": not a stepstone database");
}

TEST_CASE("a seed of -1 is refused like any negative seed", "[cli][harden][errors]") {
    test::TempDir dir;
    test::write_file(dir / "c.json", kTinyConfig);
    for (const char* seed : {"-1", "-2", "18446744073709551616", "1e3", "9223372036854775808"}) {
        INFO(seed);
        check_refused(test::run_cli({"evolve", "--config", (dir / "c.json").string(), "--db",
                                     (dir / "r.db").string(), "--seed", seed}),
                      2, std::string("--seed must be an integer from 0 to 9223372036854775807, got ") + seed);
        CHECK_FALSE(fs::exists(dir / "r.db"));
    }
}

TEST_CASE("a run config given to campaign, or a campaign config to evolve, says which it is",
          "[cli][harden][errors]") {
    test::TempDir dir;
    const std::string examples = std::string(STEPSTONE_SOURCE_DIR) + "/examples/";
    check_refused(test::run_cli({"campaign", examples + "source_quick.json", "--dir", (dir / "camp").string()}), 2,
                  "this is a run config, not a campaign config");
    CHECK_FALSE(fs::exists(dir / "camp"));
    check_refused(test::run_cli({"evolve", "--config", examples + "campaign_quick.json", "--db",
                                 (dir / "r.db").string()}),
                  2, "this is a campaign config, not a run config");
}

TEST_CASE("stats checks its outputs before printing, and points from a demo folder to its campaign",
          "[cli][harden][errors]") {
    test::TempDir dir;
    fs::create_directories(dir / "demo-out" / "campaign");
    test::make_stepstone_db(dir / "demo-out" / "campaign" / "campaign.db");
    check_refused(test::run_cli({"stats", (dir / "demo-out").string()}), 1,
                  "the campaign is in " + (dir / "demo-out" / "campaign").string());
    check_refused(test::run_cli({"stats", (dir / "demo-out" / "campaign").string(), "--csv", "/no/such/dir/x.csv"}),
                  2, "/no/such/dir/x.csv: cannot create");
}

TEST_CASE("kb merge refuses the same KB twice unless --allow-duplicates", "[cli][harden][kb]") {
    test::TempDir dir;
    kbtest::write_kb(dir / "a.db", "a", kbtest::point_kb("run-a", {{0, 0, 1.0, 0}, {3, 3, 0.5, 1}}));
    kbtest::write_kb(dir / "b.db", "b", kbtest::point_kb("run-b", {{1, 1, 1.0, 0}}));
    fs::copy_file(dir / "a.db", dir / "a-copy.db");
    const auto a = (dir / "a.db").string();
    check_refused(test::run_cli({"kb", "merge", a, a, "--out", (dir / "m.db").string()}), 2, "the same file");
    check_refused(test::run_cli({"kb", "merge", a, (dir / "b.db").string(), (dir / "a-copy.db").string(), "--out",
                                 (dir / "m.db").string()}),
                  2, "--allow-duplicates");
    CHECK_FALSE(fs::exists(dir / "m.db"));
    CHECK(test::run_cli({"kb", "merge", a, a, "--out", (dir / "m.db").string(), "--allow-duplicates"}).exit_code ==
          0);
    CHECK(kbtest::load_kb(dir / "m.db").record(0).count == 2);  // counted twice, as asked
    CHECK(test::run_cli({"kb", "merge", a, (dir / "b.db").string(), "--out", (dir / "ab.db").string()}).exit_code ==
          0);
}

TEST_CASE("sum and mo with a KB whose largest average reward is 0 warn", "[cli][harden][kb]") {
    test::TempDir dir;
    kbtest::write_kb(dir / "zero.db", "zero", kbtest::point_kb("run-z", {{0, 0, 0.0, 0}, {2, 2, 0.0, 0}}, 0.5, 15));
    kbtest::write_kb(dir / "some.db", "some", kbtest::point_kb("run-s", {{0, 0, 0.5, 0}}, 0.5, 15));
    test::write_file(dir / "t.json", kTinyTargetConfig);
    for (const char* treatment : {"sum", "mo"}) {
        INFO(treatment);
        auto result = test::run_cli({"evolve", "--config", (dir / "t.json").string(), "--db",
                                     (dir / (std::string(treatment) + ".db")).string(), "--kb",
                                     (dir / "zero.db").string(), "--treatment", treatment, "--quiet"});
        CHECK(result.exit_code == 0);
        REQUIRE(result.err_lines().size() == 1);
        CHECK_THAT(result.err_lines()[0], StartsWith("stepstone: warning: "));
        CHECK_THAT(result.err_lines()[0], Contains("largest average reward is 0"));
    }
    {
        // the KB as the user named it, relative to where they are, not its absolute path
        auto relative = test::run_cli({"evolve", "--config", "t.json", "--db", "rel.db", "--kb", "zero.db",
                                       "--treatment", "sum", "--quiet"},
                                      dir.path());
        CHECK(relative.exit_code == 0);
        REQUIRE(relative.err_lines().size() == 1);
        CHECK_THAT(relative.err_lines()[0], StartsWith("stepstone: warning: zero.db: "));
    }
    auto result = test::run_cli({"evolve", "--config", (dir / "t.json").string(), "--db", (dir / "s.db").string(),
                                 "--kb", (dir / "some.db").string(), "--treatment", "sum", "--quiet"});
    CHECK(result.exit_code == 0);
    CHECK(result.err.empty());

    // kb export and kb merge say it when they write such a KB, and only then
    for (const auto& args : std::vector<std::vector<std::string>>{
             {"kb", "export", (dir / "zero.db").string(), "--kb-name", "zero", "--out",
              (dir / "zero-out.db").string()},
             {"kb", "merge", (dir / "zero.db").string(), (dir / "zero.db").string(), "--allow-duplicates",
              "--out", (dir / "zero-merged.db").string()}}) {
        INFO(args[1]);
        result = test::run_cli(args);
        CHECK(result.exit_code == 0);
        REQUIRE(result.err_lines().size() == 1);
        CHECK_THAT(result.err_lines()[0],
                   StartsWith("stepstone: warning: ") && Contains("largest average reward is 0"));
    }
    result = test::run_cli({"kb", "export", (dir / "some.db").string(), "--kb-name", "some", "--out",
                            (dir / "some-out.db").string()});
    CHECK(result.exit_code == 0);
    CHECK(result.err.empty());
}

TEST_CASE("a mistyped command suggests the nearest one", "[cli][harden][errors]") {
    check_refused(test::run_cli({"evolv"}), 2, "did you mean 'evolve'?");
    check_refused(test::run_cli({"kb", "exprot"}), 2, "did you mean 'export'?");
    check_refused(test::run_cli({"zzzzzz"}), 2, "unknown command 'zzzzzz'");
}

TEST_CASE("a mistyped option suggests the nearest one, and extra arguments come back in order",
          "[cli][harden][errors]") {
    check_refused(test::run_cli({"evolve", "--db", "x.db", "--generatoins", "10"}), 2,
                  "unknown option '--generatoins' for stepstone evolve (did you mean '--generations'?)");
    check_refused(test::run_cli({"kb", "stats", "x.db", "--jsn"}), 2,
                  "unknown option '--jsn' for stepstone kb stats (did you mean '--json'?)");
    check_refused(test::run_cli({"demo", "--zzzzzzzz"}), 2,
                  "unknown option '--zzzzzzzz' for stepstone demo (see stepstone demo --help)");
    check_refused(test::run_cli({"kb", "stats", "a.db", "b.db", "c.db"}), 2,
                  "unexpected arguments for stepstone kb stats: b.db c.db");
}

namespace {

// the README's shell line that starts with `prefix` (joined with its '\' continuations)
std::string readme_command(const std::string& prefix) {
    const std::string readme = test::read_file(fs::path(STEPSTONE_SOURCE_DIR) / "README.md");
    const auto start = readme.find("\n" + prefix);
    REQUIRE(start != std::string::npos);
    std::string command;
    std::size_t at = start + 1;
    while (true) {
        const auto end = readme.find('\n', at);
        std::string line = readme.substr(at, end - at);
        if (!line.empty() && line.back() == '\\') {
            line.pop_back();
            command += line;
            at = end + 1;
            continue;
        }
        return command + line;
    }
}

std::string shell(const std::string& command, const fs::path& cwd) {
    const std::string full = "cd '" + cwd.string() + "' && " + command + " 2>&1";
    std::string out;
    FILE* pipe = ::popen(full.c_str(), "r");
    REQUIRE(pipe != nullptr);
    char buffer[4096];
    while (const std::size_t got = std::fread(buffer, 1, sizeof buffer, pipe)) out.append(buffer, got);
    ::pclose(pipe);
    return out;
}

}  // namespace

TEST_CASE("the README's sqlite3 saliency example prints a header and rows", "[cli][harden][docs]") {
    // scripts/setup-deps installs the shell (Debian's sqlite3): without it this test fails, never skips
    {
        INFO("no sqlite3 shell on PATH: install Debian's sqlite3 package (scripts/setup-deps does)");
        REQUIRE(std::system("command -v sqlite3 > /dev/null 2>&1") == 0);
    }
    test::TempDir dir;
    kbtest::make_run(dir / "run.db");
    REQUIRE(test::run_cli({"kb", "export", "run.db", "--out", "kb.db"}, dir.path()).exit_code == 0);
    REQUIRE(test::run_cli({"kb", "annotate", "run.db", "--kb", "kb.db", "--individuals", "front"}, dir.path())
                .exit_code == 0);
    fs::create_symlink(fs::path(STEPSTONE_SOURCE_DIR) / "queries", dir / "queries");
    const std::string out = shell(readme_command("sqlite3 -header run.db"), dir.path());
    INFO(out);
    CHECK_THAT(out, StartsWith("segment|step_start|step_end|kb_segment_id|distance|average_reward\n"));
    // one row per annotated segment of the first annotated policy
    std::size_t lines = 0;
    for (char c : out) lines += c == '\n' ? 1 : 0;
    auto connection = db::open_database(dir / "run.db", db::OpenMode::read_only);
    const auto segments = connection.query_int(
        "SELECT COUNT(*) FROM policy_segment WHERE individual_id = (SELECT MIN(individual_id) FROM policy_segment)");
    REQUIRE(segments.value_or(0) > 0);
    CHECK(static_cast<std::int64_t>(lines) == 1 + *segments);

    const std::string salient = shell(
        "sqlite3 -header run.db \".parameter set :kb_name 'run'\" \".parameter set :min_count 1\" "
        "\".parameter set :limit 10\" \".read queries/salient_segments.sql\"",
        dir.path());
    CHECK(readme_command("  `sqlite3 -header run.db").find(".read queries/salient_segments.sql") !=
          std::string::npos);
    CHECK_THAT(salient, StartsWith("kb_segment_id|"));
}

TEST_CASE("db info and db migrate say a file fails SQLite's integrity check and leave it as it was",
          "[cli][harden][db]") {
    test::TempDir dir;
    test::write_file(dir / "c.json", kSlowConfig);
    REQUIRE(test::run_cli({"evolve", "--config", (dir / "c.json").string(), "--db", (dir / "run.db").string(),
                           "--generations", "3", "--quiet"})
                .exit_code == 0);
    const auto whole = test::run_cli({"db", "info", (dir / "run.db").string()});
    CHECK(whole.exit_code == 0);
    CHECK_THAT(whole.out, Contains("integrity       ok"));

    // the cell pointers of a b-tree page in the second half of the file (its
    // first byte: 0x02, 0x05, 0x0a or 0x0d) overwritten: header and schema still read
    const auto run_bytes = test::read_file(dir / "run.db");
    const std::size_t pages = run_bytes.size() / 4096;
    REQUIRE(pages > 8);
    std::size_t page = pages / 2;
    const auto btree = [&](std::size_t p) {
        const char type = run_bytes[p * 4096];
        return type == 0x02 || type == 0x05 || type == 0x0a || type == 0x0d;
    };
    while (page < pages && !btree(page)) ++page;
    REQUIRE(page < pages);
    std::string damaged = run_bytes;
    for (std::size_t k = 0; k < 600; ++k) damaged[page * 4096 + 8 + k] = '\xff';
    test::write_file(dir / "damaged.db", damaged);
    check_refused(test::run_cli({"db", "info", (dir / "damaged.db").string()}), 1,
                  "fails SQLite's integrity check");
    CHECK(test::read_file(dir / "damaged.db") == damaged);
    // nor is it "up to date" for db migrate, which leaves it as it was
    check_refused(test::run_cli({"db", "migrate", (dir / "damaged.db").string()}), 1,
                  "fails SQLite's integrity check");
    CHECK(test::read_file(dir / "damaged.db") == damaged);
}

TEST_CASE("a thread count of 0 is refused by evolve and kb calibrate in one line (1 to 1024)",
          "[cli][harden][errors]") {
    test::TempDir dir;
    test::write_file(dir / "c.json", kTinyConfig);
    const auto evolve = test::run_cli({"evolve", "--config", (dir / "c.json").string(), "--db",
                                       (dir / "run.db").string(), "--threads", "0"});
    check_refused(evolve, 2, "--threads");
    CHECK_FALSE(fs::exists(dir / "run.db"));
    REQUIRE(test::run_cli({"evolve", "--config", (dir / "c.json").string(), "--db", (dir / "run.db").string(),
                           "--threads", "1", "--quiet"})
                .exit_code == 0);
    check_refused(test::run_cli({"kb", "calibrate", (dir / "run.db").string(), "--threads", "0"}), 2,
                  "--threads");
}

TEST_CASE("a schema damaged into a long token is one short line, not the token", "[cli][harden][db]") {
    test::TempDir dir;
    kbtest::make_run(dir / "run.db");
    REQUIRE(test::run_cli({"kb", "export", (dir / "run.db").string(), "--out", (dir / "kb.db").string()})
                .exit_code == 0);
    // a table's stored CREATE statement cut into an unterminated 600-character identifier
    std::string token(600, 'a');
    test::raw_exec(dir / "kb.db",
                   "PRAGMA writable_schema = ON; UPDATE sqlite_schema SET sql = 'CREATE TABLE "
                   "kb_source(a, \"" +
                       token + " (x y z)' WHERE name = 'kb_source';");
    const auto result = test::run_cli({"kb", "stats", (dir / "kb.db").string()});
    CHECK(result.exit_code == 1);
    REQUIRE(result.err_lines().size() == 1);
    CHECK_THAT(result.err, Contains("malformed database schema (kb_source)"));
    CHECK(result.err.size() < 300);  // SQLite's own message quoted the whole 600-character token
}
