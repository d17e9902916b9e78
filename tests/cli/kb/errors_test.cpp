#include <catch2/catch.hpp>

#include "db/database.hpp"
#include "support/db_files.hpp"
#include "support/kb_fixtures.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;
using Catch::Matchers::StartsWith;

namespace {

// one stderr line, the expected exit code, the message naming what is wrong
void check_error(const test::CliResult& result, int exit_code, const std::string& needle) {
    INFO(result.err);
    CHECK(result.exit_code == exit_code);
    REQUIRE(result.err_lines().size() == 1);
    CHECK_THAT(result.err_lines()[0], StartsWith("stepstone: error: "));
    CHECK_THAT(result.err_lines()[0], Contains(needle));
}

}  // namespace

TEST_CASE("every kb subcommand and shape show an example in --help", "[cli][kb][help]") {
    for (const auto& args : std::vector<std::vector<std::string>>{{"kb", "--help"},
                                                                  {"kb", "export", "--help"},
                                                                  {"kb", "merge", "--help"},
                                                                  {"kb", "randomize", "--help"},
                                                                  {"kb", "calibrate", "--help"},
                                                                  {"kb", "stats", "--help"},
                                                                  {"kb", "annotate", "--help"},
                                                                  {"shape", "--help"}}) {
        INFO(args[0] << " " << args[1]);
        auto result = test::run_cli(args);
        CHECK(result.exit_code == 0);
        CHECK_THAT(result.out, Contains("Example:"));
        CHECK_THAT(result.out, Contains("stepstone " + args[0]));
    }
}

TEST_CASE("kb commands refuse missing, newer-schema and foreign files with one line and exit 1",
          "[cli][kb][errors]") {
    test::TempDir dir;
    test::make_newer_stepstone(dir / "newer.db");
    test::make_foreign_sqlite(dir / "foreign.db");
    kbtest::write_kb(dir / "a.db", "a", kbtest::point_kb("run-a", {{0, 0, 1, 0}}));
    const auto before = kbtest::files_in(dir.path());
    const auto a = (dir / "a.db").string();
    const auto out = (dir / "out.db").string();

    check_error(test::run_cli({"kb", "stats", (dir / "newer.db").string()}), 1, "newer.db: schema version");
    check_error(test::run_cli({"kb", "merge", a, (dir / "newer.db").string(), "--out", out}), 1,
                "is newer than");
    check_error(test::run_cli({"kb", "export", (dir / "foreign.db").string(), "--out", out}), 1,
                "foreign.db: not a stepstone database");
    check_error(test::run_cli({"kb", "randomize", (dir / "absent.db").string(), "--out", out, "--seed", "1"}),
                1, "absent.db: no such file");
    check_error(test::run_cli({"shape", "--kb", a, "--run", (dir / "absent.db").string()}), 1,
                "absent.db: no such file");
    check_error(test::run_cli({"kb", "export", a, "--kb-name", "run", "--out", out}), 1,
                "a.db: no knowledge base named \"run\"");
    // a KB file is not a run file
    check_error(test::run_cli({"kb", "calibrate", a}), 1, "a.db");
    CHECK(kbtest::files_in(dir.path()) == before);
}

TEST_CASE("a KB file with a NaN value or an infinite reward is refused with one line", "[cli][kb][errors]") {
    test::TempDir dir;
    kbtest::write_kb(dir / "nan.db", "a", kbtest::point_kb("run-a", {{0, 0, 1, 0}, {3, 3, 1, 0}}));
    {
        // segment 1's first value becomes a float NaN (0x7fc00000, little endian)
        auto connection = db::open_database(dir / "nan.db", db::OpenMode::read_write);
        connection.exec("UPDATE kb_segment SET segment_values = X'0000C07F00004040' WHERE id = 1");
    }
    kbtest::write_kb(dir / "inf.db", "b", kbtest::point_kb("run-b", {{0, 0, 1, 0}}));
    {
        // SQLite turns a NaN into NULL (refused by NOT NULL), but stores an infinity
        auto connection = db::open_database(dir / "inf.db", db::OpenMode::read_write);
        connection.exec("UPDATE kb_segment SET cum_reward = 1e999");
    }
    const auto out = (dir / "out.db").string();
    check_error(test::run_cli({"kb", "stats", (dir / "nan.db").string()}), 1, "nan.db: knowledge base \"a\"");
    check_error(test::run_cli({"kb", "randomize", (dir / "nan.db").string(), "--out", out, "--seed", "1"}), 1,
                "nan.db");
    check_error(
        test::run_cli({"kb", "merge", (dir / "inf.db").string(), (dir / "nan.db").string(), "--out", out}), 1,
        "inf.db: knowledge base \"b\" segment 0 has a non-finite cum_reward (inf)");
    CHECK_FALSE(std::filesystem::exists(out));
}

TEST_CASE("annotate and shape refuse a KB of other channels and leave the run file unchanged",
          "[cli][kb][errors]") {
    test::TempDir dir;
    kbtest::make_run(dir / "run.db");
    kbtest::write_kb(dir / "two.db", "two", kbtest::point_kb("run-a", {{0, 0, 1, 0}}));  // 2 channels
    const std::string run_before = test::read_file(dir / "run.db");
    const auto before = kbtest::files_in(dir.path());

    check_error(
        test::run_cli({"kb", "annotate", (dir / "run.db").string(), "--kb", (dir / "two.db").string()}), 1,
        (dir / "two.db").string() + ": knowledge base \"two\" has 2 channels, the behaviours of " +
            (dir / "run.db").string() + " have 15");
    check_error(
        test::run_cli({"shape", "--kb", (dir / "two.db").string(), "--run", (dir / "run.db").string()}), 1,
        "has 2 channels");
    CHECK(test::read_file(dir / "run.db") == run_before);
    CHECK(kbtest::files_in(dir.path()) == before);

    // a different KB under a name the run file already uses: refused, unless copied under another name
    REQUIRE(test::run_cli({"kb", "export", (dir / "run.db").string(), "--out", (dir / "kb.db").string()})
                .exit_code == 0);
    REQUIRE(test::run_cli({"kb", "randomize", (dir / "kb.db").string(), "--out", (dir / "other.db").string(),
                           "--seed", "1", "--name", "run"})
                .exit_code == 0);
    check_error(
        test::run_cli({"kb", "annotate", (dir / "run.db").string(), "--kb", (dir / "other.db").string()}), 1,
        "run.db: already holds a different knowledge base named \"run\"; choose another name with --as");
    CHECK(test::read_file(dir / "run.db") == run_before);
    auto renamed = test::run_cli({"kb", "annotate", (dir / "run.db").string(), "--kb",
                                  (dir / "other.db").string(), "--as", "control"});
    CHECK(renamed.exit_code == 0);
    CHECK_THAT(renamed.out, Contains("\"control\", copied into the run file"));
}

TEST_CASE("kb merge, randomize and export refuse an existing output without --force and replace it with it",
          "[cli][kb][errors]") {
    test::TempDir dir;
    kbtest::write_kb(dir / "a.db", "a", kbtest::point_kb("run-a", {{0, 0, 1, 0}}));
    kbtest::write_kb(dir / "b.db", "b", kbtest::point_kb("run-b", {{5, 5, 1, 0}}));
    test::write_file(dir / "taken.db", "precious");
    const auto a = (dir / "a.db").string();
    const auto taken = (dir / "taken.db").string();

    check_error(test::run_cli({"kb", "merge", a, (dir / "b.db").string(), "--out", taken}), 2,
                "taken.db: already exists (use --force to overwrite)");
    check_error(test::run_cli({"kb", "randomize", a, "--out", taken, "--seed", "3"}), 2, "already exists");
    check_error(test::run_cli({"kb", "export", a, "--kb-name", "a", "--out", taken}), 2, "already exists");
    CHECK(test::read_file(dir / "taken.db") == "precious");

    auto result = test::run_cli({"kb", "randomize", a, "--out", taken, "--seed", "3", "--force"});
    CHECK(result.exit_code == 0);
    CHECK(kbtest::load_kb(dir / "taken.db").size() == 1);
}

TEST_CASE("bad flag values of the kb commands and shape are usage errors with exit 2", "[cli][kb][errors]") {
    test::TempDir dir;
    kbtest::write_kb(dir / "a.db", "a", kbtest::point_kb("run-a", {{0, 0, 1, 0}}));
    const auto a = (dir / "a.db").string();
    check_error(test::run_cli({"kb", "merge", a, "--out", (dir / "m.db").string()}), 2, "at least two");
    check_error(test::run_cli({"kb", "calibrate", a, "--deltas", "1,-2"}), 2, "--deltas");
    check_error(test::run_cli({"kb", "annotate", a, "--kb", a, "--individuals", "some"}), 2, "--individuals");
    check_error(test::run_cli({"kb", "randomize", a, "--out", (dir / "r.db").string(), "--seed", "x"}), 2,
                "--seed");
    CHECK(kbtest::files_in(dir.path()) == std::vector<std::string>{"a.db"});
    kbtest::make_run(dir / "run.db");
    check_error(
        test::run_cli({"shape", "--kb", a, "--run", (dir / "run.db").string(), "--individual", "first"}), 2,
        "--individual");
    check_error(test::run_cli({"kb", "calibrate", (dir / "run.db").string(), "--segment-width", "0"}), 2,
                "--segment-width");
}
