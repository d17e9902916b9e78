// stepstone report and render through the real binary: what a report holds,
// that it refers only to its own files, and that failures leave nothing.

#include <catch2/catch.hpp>
#include <cstdio>
#include <filesystem>
#include <set>

#include "core/text.hpp"
#include "db/database.hpp"
#include "db/kb_store.hpp"
#include "images.hpp"
#include "runs.hpp"
#include "runs/run_store.hpp"
#include "support/db_files.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using test::run_cli;
namespace fs = std::filesystem;

namespace {

// every reference of index.html is a plain file name of the report, and every
// file of the report but index.html is referred to
void check_self_contained(const fs::path& out) {
    const auto html = test::read_file(out / "index.html");
    CHECK(html.find("http://") == std::string::npos);
    CHECK(html.find("https://") == std::string::npos);
    CHECK(html.find("<script") == std::string::npos);
    std::set<std::string> referred;
    for (const auto& ref : reporttest::references(html)) {
        CAPTURE(ref);
        CHECK(ref.find('/') == std::string::npos);
        CHECK(ref.find(':') == std::string::npos);
        CHECK(fs::is_regular_file(out / ref));
        referred.insert(ref);
    }
    for (const auto& name : reporttest::entries(out)) {
        if (name != "index.html") CHECK(referred.count(name) == 1);
    }
}

// the single error line, and no report or temporary directory left in `dir`
void check_refused(const test::CliResult& result, const fs::path& dir, const std::vector<std::string>& before,
                   const std::string& message) {
    CHECK(result.exit_code != 0);
    REQUIRE(result.err_lines().size() == 1);
    CHECK(result.err_lines()[0].find(message) != std::string::npos);
    CHECK(reporttest::entries(dir) == before);
}

}  // namespace

TEST_CASE("a run's report holds its figures and refers only to files beside it", "[report]") {
    test::TempDir dir;
    reporttest::make_run(dir / "run.db");
    const auto result = run_cli({"report", (dir / "run.db").string(), "--out", (dir / "rep").string(), "--quiet"});
    REQUIRE(result.exit_code == 0);
    CHECK(result.out.find("open " + (dir / "rep" / "index.html").string()) != std::string::npos);
    for (const auto* name : {"rewards.png", "milestones.png", "arena.png", "trajectory.png", "trajectory.svg",
                             "trajectory-saliency.png", "kb-histogram.png", "kb-growth.png"}) {
        CAPTURE(name);
        REQUIRE(fs::exists(dir / "rep" / name));
    }
    check_self_contained(dir / "rep");
    CHECK(reporttest::check_png(test::read_file(dir / "rep" / "rewards.png"), 800, 460).empty());
    CHECK(reporttest::check_svg(test::read_file(dir / "rep" / "trajectory.svg")).empty());
    const auto html = test::read_file(dir / "rep" / "index.html");
    // the provenance: the digest that `stepstone db digest` prints
    const auto digest = run_cli({"db", "digest", (dir / "run.db").string()});
    REQUIRE(digest.exit_code == 0);
    const auto hex = digest.out.substr(0, digest.out.find_first_of(" \n"));
    CHECK(html.find(hex) != std::string::npos);

    // an existing report is refused without --force, replaced with it
    const auto again = run_cli({"report", (dir / "run.db").string(), "--out", (dir / "rep").string()});
    CHECK(again.exit_code == 2);
    CHECK(again.err_lines().at(0).find("exists (use --force to replace it)") != std::string::npos);
    test::write_file(dir / "rep" / "stale.txt", "old");
    REQUIRE(run_cli({"report", (dir / "run.db").string(), "--out", (dir / "rep").string(), "--force", "--quiet"})
                .exit_code == 0);
    CHECK_FALSE(fs::exists(dir / "rep" / "stale.txt"));
    CHECK(fs::exists(dir / "rep" / "index.html"));
}

TEST_CASE("a campaign's report compares the treatments and shows the KB and the best policies", "[report]") {
    test::TempDir dir;
    reporttest::make_campaign(dir / "camp");
    const auto result = run_cli({"report", (dir / "camp").string(), "--out", (dir / "rep").string(), "--quiet"});
    REQUIRE(result.exit_code == 0);
    for (const auto* name :
         {"successes.png", "best-of-run.png", "treatment-rewards.png", "treatment-shaping.png",
          "treatment-medians.png", "kaplan-meier.png", "milestone-shares.png", "kb-histogram.png",
          "source-best.svg", "source-best-saliency.png", "target-best.svg"}) {
        CAPTURE(name);
        CHECK(fs::exists(dir / "rep" / name));
    }
    check_self_contained(dir / "rep");
    const auto html = test::read_file(dir / "rep" / "index.html");
    CHECK(html.find("Mann-Whitney") != std::string::npos);
    CHECK(html.find("sum vs none") != std::string::npos);
    CHECK(html.find("target/sum-rand/seed-2.db") != std::string::npos);
    // the treatments table ends with the shaping signal and the ball-collecting policies
    CHECK(html.find("<th>with a ball</th>") != std::string::npos);
    CHECK(html.find("r_max, gen. ") != std::string::npos);
    // the milestones: Kaplan-Meier figure, log-rank and median tables
    CHECK(html.find("Log-rank tests of the time to each milestone") != std::string::npos);
    CHECK(html.find("Kaplan-Meier median generation") != std::string::npos);
    CHECK(reporttest::check_png(test::read_file(dir / "rep" / "kaplan-meier.png"), 1000, 980).empty());
    // the shaping signal as sum adds it: r_max over each KB's largest average, read here from the KB files
    const auto largest = [&](const char* file) {
        auto connection = db::open_database(dir / "camp" / file, db::OpenMode::read_only);
        char text[32];
        std::snprintf(text, sizeof text, "%.3f", db::load_kb(connection).kb.max_average());
        return std::string(text);
    };
    CHECK(html.find("mean r_max / A") != std::string::npos);
    CHECK(html.find(concat("(kb ", largest("kb/kb.db"), ", kb-rand ", largest("kb/kb-rand.db"), ")")) !=
          std::string::npos);

    // the best target run's reward decides the heading: a best reward of 0 is no best policy
    const auto best_target = [&](double reward) {
        {
            auto connection = db::open_database(dir / "camp" / "campaign.db", db::OpenMode::read_write);
            connection.exec(
                concat("UPDATE campaign_run SET best_reward = 0 WHERE step = 'target'; "
                       "UPDATE campaign_run SET best_reward = ",
                       reward, " WHERE file = 'target/sum/seed-1.db'"));
        }
        REQUIRE(run_cli({"report", (dir / "camp").string(), "--out", (dir / "rep").string(), "--quiet",
                         "--force"})
                    .exit_code == 0);
        return test::read_file(dir / "rep" / "index.html");
    };
    const auto none_scored = best_target(0.0);
    CHECK(none_scored.find("No target policy scored") != std::string::npos);
    CHECK(none_scored.find("The best target policy") == std::string::npos);
    const auto one_scored = best_target(0.25);
    CHECK(one_scored.find("The best target policy") != std::string::npos);
    CHECK(one_scored.find("The best policy of target/sum/seed-1.db") != std::string::npos);
}

TEST_CASE("a run file older than the milestones still reports, and says what it lacks", "[report]") {
    test::TempDir dir;
    reporttest::make_run(dir / "run.db");
    test::make_schema4_run(dir / "run.db");  // as schema 4 wrote it: no milestone columns
    const auto before = test::read_file(dir / "run.db");
    const auto result =
        run_cli({"report", (dir / "run.db").string(), "--out", (dir / "rep").string(), "--quiet"});
    INFO(result.err);
    REQUIRE(result.exit_code == 0);
    CHECK(fs::exists(dir / "rep" / "rewards.png"));
    CHECK_FALSE(fs::exists(dir / "rep" / "milestones.png"));
    const auto html = test::read_file(dir / "rep" / "index.html");
    CHECK(html.find("predates milestone recording (schema 0005)") != std::string::npos);
    CHECK(html.find("none: schema version 4") != std::string::npos);
    CHECK(test::read_file(dir / "run.db") == before);
}

TEST_CASE("a report of a run with no generation, of a foreign file or into an unwritable place fails cleanly",
          "[report]") {
    test::TempDir dir;
    // a run row and no generation: what a run killed before its first commit leaves
    {
        auto connection = db::open_database(dir / "empty.db", db::OpenMode::create);
        runs::RunRecord run;
        run.task = "source";
        run.seed = 1;
        run.config = nlohmann::json::parse(R"({"task": {"kind": "source"}})");
        runs::insert_run(connection, run, "test");
    }
    test::write_file(dir / "foreign.db", "this is not a database\n");
    test::write_file(dir / "file.txt", "x");
    reporttest::make_run(dir / "run.db");
    const auto before = reporttest::entries(dir.path());

    check_refused(run_cli({"report", (dir / "empty.db").string(), "--out", (dir / "rep").string()}), dir.path(), before,
                  "empty.db: the run has no generation yet, nothing to report");
    check_refused(run_cli({"report", (dir / "foreign.db").string(), "--out", (dir / "rep").string()}), dir.path(), before,
                  "foreign.db");
    check_refused(run_cli({"report", (dir / "run.db").string(), "--out", (dir / "file.txt" / "rep").string()}), dir.path(),
                  before, "file.txt is not a directory");
    check_refused(run_cli({"report", (dir / "run.db").string(), "--out", (dir / "absent" / "rep").string()}),
                  dir.path(), before, "absent does not exist");
    check_refused(run_cli({"report", (dir / "nowhere").string(), "--out", (dir / "rep").string()}), dir.path(), before,
                  "no such file or directory");
    check_refused(run_cli({"report", dir.path().string(), "--out", (dir / "rep").string()}), dir.path(), before,
                  "no campaign.db here");
}

TEST_CASE("render draws a stored policy as PNG or SVG, and refuses bad options with one line", "[report]") {
    test::TempDir dir;
    reporttest::make_run(dir / "run.db");
    const auto png = run_cli({"render", (dir / "run.db").string(), "--out", (dir / "t.png").string(), "--steps",
                              "10:150", "--saliency-out", (dir / "s.svg").string()});
    REQUIRE(png.exit_code == 0);
    CHECK(reporttest::check_png(test::read_file(dir / "t.png"), 800, 680).empty());
    CHECK(reporttest::check_svg(test::read_file(dir / "s.svg")).empty());
    const auto svg = run_cli({"render", (dir / "run.db").string(), "--out", (dir / "t.svg").string(),
                              "--individual", "best", "--steps", "0:30"});
    REQUIRE(svg.exit_code == 0);
    CHECK(reporttest::parse_svg(test::read_file(dir / "t.svg")).titles == 30);
    // it says which steps it drew, not only how many the start ran
    CHECK(svg.out.find("steps 0 to 30 drawn (30)") != std::string::npos);
    CHECK(png.out.find("steps 10 to 150 drawn (140)") != std::string::npos);

    const auto before = reporttest::entries(dir.path());
    const auto refused = [&](const std::vector<std::string>& extra, const std::string& message) {
        std::vector<std::string> args{"render", (dir / "run.db").string()};
        args.insert(args.end(), extra.begin(), extra.end());
        check_refused(run_cli(args), dir.path(), before, message);
    };
    refused({"--out", (dir / "x.jpg").string()}, "must end in .png or .svg");
    refused({"--out", (dir / "t.png").string()}, "t.png exists (use --force to replace it)");
    refused({"--out", (dir / "x.png").string(), "--steps", "50:20"}, "--steps must be A:B with A < B");
    refused({"--out", (dir / "x.png").string(), "--steps", "abc"}, "--steps must be A:B");
    refused({"--out", (dir / "x.png").string(), "--start", "3"}, "--start must be within 1 to 1");
    refused({"--out", (dir / "x.png").string(), "--individual", "99999"}, "99999");
    refused({"--out", (dir / "x.png").string(), "--kb", (dir / "none.db").string()}, "none.db");
}

TEST_CASE("a campaign whose target runs have not all started compares the finished ones", "[report]") {
    test::TempDir dir;
    reporttest::make_campaign(dir / "camp");
    {
        // as a running campaign leaves it: one target run not started yet
        auto connection = db::open_database(dir / "camp" / "campaign.db", db::OpenMode::read_write);
        connection.exec(
            "UPDATE campaign_run SET status = 'pending', generations_done = -1, best_reward = NULL, "
            "digest = NULL WHERE file = 'target/sum/seed-2.db'");
    }
    fs::remove(dir / "camp" / "target" / "sum" / "seed-2.db");
    const auto result =
        run_cli({"report", (dir / "camp").string(), "--out", (dir / "rep").string(), "--quiet"});
    INFO(result.err);
    REQUIRE(result.exit_code == 0);
    const auto html = test::read_file(dir / "rep" / "index.html");
    CHECK(html.find("1 target runs have not finished") != std::string::npos);
    CHECK(fs::exists(dir / "rep" / "kaplan-meier.png"));
    CHECK(html.find("Log-rank tests") != std::string::npos);
}
