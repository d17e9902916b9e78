#include <catch2/catch.hpp>

#include <nlohmann/json.hpp>

#include "db/database.hpp"
#include "support/db_files.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;
using Catch::Matchers::StartsWith;

TEST_CASE("an unknown flag is a usage error: exit 2, one stderr line, no output file", "[cli][errors]") {
    test::TempDir dir;
    auto result = test::run_cli({"db", "info", "--bogus", "x.db"}, dir.path());
    CHECK(result.exit_code == 2);
    REQUIRE(result.err_lines().size() == 1);
    CHECK_THAT(result.err_lines()[0], StartsWith("stepstone: error: "));
    CHECK_THAT(result.err_lines()[0], Contains("--bogus"));
    CHECK(std::filesystem::is_empty(dir.path()));

    result = test::run_cli({"no-such-command"});
    CHECK(result.exit_code == 2);
    CHECK(result.err_lines().size() == 1);

    result = test::run_cli({});
    CHECK(result.exit_code == 2);
    CHECK(result.err_lines().size() == 1);
}

TEST_CASE("the --help of every level shows an example and exits 0", "[cli][help]") {
    for (const auto& args : std::vector<std::vector<std::string>>{
             {"--help"}, {"db", "--help"}, {"db", "info", "--help"}, {"db", "migrate", "--help"}, {"db", "digest", "--help"}, {"demo", "--help"},
             {"evolve", "--help"}, {"replay", "--help"}, {"simulate", "--help"}, {"bench", "--help"},
             {"campaign", "--help"}, {"stats", "--help"}, {"render", "--help"}, {"report", "--help"}}) {
        auto result = test::run_cli(args);
        INFO(args.front() << " " << args.back());
        CHECK(result.exit_code == 0);
        CHECK_THAT(result.out, Contains("Example:"));
        CHECK_THAT(result.out, Contains("stepstone "));
    }
    auto version = test::run_cli({"--version"});
    CHECK(version.exit_code == 0);
    CHECK_THAT(version.out, StartsWith("stepstone "));
}

TEST_CASE("bench lists its cases, or in a build without it says so in one line", "[cli][bench][errors]") {
    // the sanitize preset configures STEPSTONE_BENCH=OFF; the ci and release presets build it
    const auto result = test::run_cli({"bench", "--list"});
    if (result.exit_code == 0) {
        CHECK_THAT(result.out, Contains("episode") && Contains("shaped-1.83"));
    } else {
        CHECK(result.exit_code == 2);
        REQUIRE(result.err_lines().size() == 1);
        CHECK_THAT(result.err_lines()[0], Contains("STEPSTONE_BENCH=OFF"));
        CHECK(result.out.empty());
    }
}

TEST_CASE("db info refuses bad files with exit 1, one line, the file unchanged", "[cli][db][errors]") {
    test::TempDir dir;
    test::write_file(dir / "passwd", test::read_file("/etc/passwd"));
    test::write_file(dir / "empty.db", "");
    test::make_truncated_stepstone(dir / "truncated.db");
    test::make_foreign_sqlite(dir / "foreign.db");
    test::make_newer_stepstone(dir / "newer.db");
    for (const char* name : {"passwd", "empty.db", "truncated.db", "foreign.db", "newer.db", "absent.db"}) {
        INFO(name);
        const auto path = dir / name;
        const std::string before = std::filesystem::exists(path) ? test::read_file(path) : "";
        auto result = test::run_cli({"db", "info", path.string()});
        CHECK(result.exit_code == 1);
        REQUIRE(result.err_lines().size() == 1);
        CHECK_THAT(result.err_lines()[0], StartsWith("stepstone: error: " + path.string() + ": "));
        CHECK(result.out.empty());
        if (std::filesystem::exists(path)) CHECK(test::read_file(path) == before);
        // migrate refuses them as well, without writing
        result = test::run_cli({"db", "migrate", path.string()});
        CHECK(result.exit_code == 1);
        if (std::filesystem::exists(path)) CHECK(test::read_file(path) == before);
    }
}

TEST_CASE("db info lists the schema version and table row counts", "[cli][db]") {
    test::TempDir dir;
    test::make_stepstone_db(dir / "run.db");
    auto result = test::run_cli({"db", "info", (dir / "run.db").string(), "--json"});
    REQUIRE(result.exit_code == 0);
    const auto json = nlohmann::json::parse(result.out);
    CHECK(json["application_id"] == db::kApplicationId);
    CHECK(json["schema_version"] == db::latest_schema_version());
    // make_stepstone_db writes 200 meta rows
    CHECK(json["tables"]["meta"] == 200);

    result = test::run_cli({"db", "info", (dir / "run.db").string()});
    REQUIRE(result.exit_code == 0);
    CHECK_THAT(result.out, Contains("0x53545053"));
    CHECK_THAT(result.out, Contains("meta"));
}

TEST_CASE("db migrate upgrades an old file and reports the versions", "[cli][db]") {
    test::TempDir dir;
    test::make_old_stepstone(dir / "old.db");
    auto result = test::run_cli({"db", "migrate", (dir / "old.db").string()});
    REQUIRE(result.exit_code == 0);
    CHECK_THAT(result.out, Contains("schema version 0 -> " + std::to_string(db::latest_schema_version())));
    result = test::run_cli({"db", "migrate", (dir / "old.db").string()});
    CHECK_THAT(result.out, Contains("up to date"));
}

TEST_CASE("demo without its example configs is a usage error", "[cli][demo][errors]") {
    test::TempDir dir;
    auto result = test::run_cli({"demo", "--dir", (dir / "out").string(), "--examples", (dir / "none").string()});
    CHECK(result.exit_code == 2);
    CHECK(result.err_lines().size() == 1);
    CHECK_THAT(result.err, Contains("campaign_quick.json: no such file"));
}
