// A campaign with seeded treatments (lib/exp/campaign, the `seed` block):
// the seeded runs are seeded from the best source run and equal the same
// evolve runs alone, and stats, pool and report treat "seed" and "seed-sum"
// like the paper's treatments, hyphen and all.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "db/database.hpp"
#include "support/campaigns.hpp"
#include "support/db_files.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;

namespace campaignseedtest {

// tiny_campaign_json's source and KB, and three treatments: none, seed, seed-sum
std::string seeded_campaign_json() {
    auto json = nlohmann::json::parse(test::tiny_campaign_json(2));
    json["target"]["treatments"] = {"none", "seed", "seed-sum"};
    json["seed"] = {{"from", "best"}, {"with", "best"}, {"count", 4}};
    return json.dump(2);
}

std::string run_treatment(const std::filesystem::path& run) {
    auto connection = db::open_database(run, db::OpenMode::read_only);
    auto select = connection.prepare("SELECT treatment FROM run");
    REQUIRE(select.step());
    return select.column_text(0);
}

}  // namespace campaignseedtest

using campaignseedtest::run_treatment;

TEST_CASE(
    "a campaign's seed and seed-sum runs are seeded from the best source run, and stats, pool and "
    "report list them",
    "[exp][campaign][seed][cli]") {
    test::TempDir dir;
    test::write_file(dir / "c.json", campaignseedtest::seeded_campaign_json());
    const auto dry = test::run_campaign(dir, "dry", {"--dry-run"});
    CHECK(dry.exit_code == 0);
    CHECK_THAT(dry.out, Contains("seed     best of the best source run, at most 4") &&
                            Contains("3 treatments (none, seed, seed-sum)"));

    const auto result = test::run_campaign(dir, "camp", {"--jobs", "2"});
    INFO(result.err);
    REQUIRE(result.exit_code == 0);
    CHECK_THAT(result.out, Contains("runs 7") && Contains("finished 7") && Contains("failed 0"));
    const auto camp = dir / "camp";
    CHECK(run_treatment(camp / "target" / "none" / "seed-1.db") == "none");
    CHECK(run_treatment(camp / "target" / "seed" / "seed-1.db") == "seed");
    CHECK(run_treatment(camp / "target" / "seed-sum" / "seed-2.db") == "seed-sum");

    // the seed-sum run of seed 2 made by hand: the campaign's KB, its only source run as the seed
    const auto alone = test::run_cli({"evolve",
                                      "--config",
                                      (camp / "config" / "target.json").string(),
                                      "--db",
                                      (dir / "alone.db").string(),
                                      "--seed",
                                      "2",
                                      "--generations",
                                      "2",
                                      "--kb",
                                      (camp / "kb" / "kb.db").string(),
                                      "--treatment",
                                      "sum",
                                      "--seed-from",
                                      (camp / "source" / "seed-4.db").string(),
                                      "--seed-with",
                                      "best",
                                      "--seed-count",
                                      "4",
                                      "--quiet"});
    REQUIRE(alone.exit_code == 0);
    CHECK(test::file_digest(dir / "alone.db") ==
          test::file_digest(camp / "target" / "seed-sum" / "seed-2.db"));

    // stats: the text tables, the runs and events CSVs, every pair of the tests
    const auto stats =
        test::run_cli({"stats", camp.string(), "--threshold", "0", "--runs-csv", (dir / "runs.csv").string(),
                       "--events-csv", (dir / "events.csv").string(), "--tests-csv",
                       (dir / "tests.csv").string(), "--logrank-csv", (dir / "logrank.csv").string()});
    INFO(stats.err);
    REQUIRE(stats.exit_code == 0);
    CHECK_THAT(stats.out, Contains("\nseed ") && Contains("\nseed-sum ") && Contains("\nnone "));
    const std::string runs_csv = test::read_file(dir / "runs.csv");
    CHECK_THAT(runs_csv, Contains("\nseed,1,2,") && Contains("\nseed-sum,2,2,"));
    CHECK_THAT(test::read_file(dir / "events.csv"), Contains("\nseed-sum,1,pickup,"));
    const std::string tests_csv = test::read_file(dir / "tests.csv");
    CHECK_THAT(tests_csv,
               Contains("\nnone,seed,") && Contains("\nnone,seed-sum,") && Contains("\nseed,seed-sum,"));
    CHECK_THAT(test::read_file(dir / "logrank.csv"), Contains("\nseed,seed-sum,pickup,"));

    // pool reads the names back, and draws their Kaplan-Meier curves
    const auto pool = test::run_cli({"pool", "--runs", (dir / "runs.csv").string(), "--events",
                                     (dir / "events.csv").string(), "--threshold", "0", "--kaplan-meier",
                                     (dir / "km.png").string()});
    INFO(pool.err);
    CHECK(pool.exit_code == 0);
    CHECK_THAT(pool.out, Contains("\nseed-sum ") && Contains("seed-sum"));
    CHECK(std::filesystem::file_size(dir / "km.png") > 0);

    // the report's page names them
    const auto report =
        test::run_cli({"report", camp.string(), "--out", (dir / "report").string(), "--quiet"});
    INFO(report.err);
    REQUIRE(report.exit_code == 0);
    CHECK_THAT(test::read_file(dir / "report" / "index.html"), Contains("seed-sum"));

    // a resume has nothing left to do
    const auto resumed = test::run_campaign(dir, "camp", {"--resume"});
    CHECK(resumed.exit_code == 0);
    CHECK_THAT(resumed.out, Contains("already_finished 7"));
}
