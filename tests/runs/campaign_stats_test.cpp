// stepstone stats on a tiny campaign whose best rewards, r_max and ball
// counts are set by hand in its run files (lib/runs/campaign_stats.cpp):
// success counts, the shaping signal, quartiles and Mann-Whitney tests worked
// by hand, and the errors for runs that are missing, corrupt or short.
#include <algorithm>
#include <catch2/catch.hpp>
#include <map>

#include "db/database.hpp"
#include "support/campaigns.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;

namespace {

// every generation of a run file gets best_reward = value (its best-of-run at any generation)
void set_best(const std::filesystem::path& run, double value) {
    auto connection = db::open_database(run, db::OpenMode::read_write);
    auto update = connection.prepare("UPDATE generation SET best_reward = ?1");
    update.bind(1, value);
    update.step();
}

// best-of-run rewards chosen by hand for seeds 1 and 2 of each treatment
void set_hand_bests(const std::filesystem::path& camp) {
    const std::map<std::string, std::pair<double, double>> best = {{"none", {0.125, 0.25}},
                                                                   {"sum", {0.625, 0.75}},
                                                                   {"mo", {0.375, 0.875}},
                                                                   {"sum-rand", {0.0, 0.0}},
                                                                   {"mo-rand", {0.0, 0.5}}};
    for (const auto& [treatment, values] : best) {
        set_best(camp / "target" / treatment / "seed-1.db", values.first);
        set_best(camp / "target" / treatment / "seed-2.db", values.second);
    }
}

// r_max by hand for the sum runs (seed 1: 0.875 before generation 2, 0.25 in
// it; seed 2: 0.75 throughout), and 3 ball-collecting policies in mo seed 1
void set_hand_signal(const std::filesystem::path& camp) {
    {
        auto connection = db::open_database(camp / "target" / "sum" / "seed-1.db", db::OpenMode::read_write);
        connection.exec("UPDATE individual SET r_max = CASE WHEN generation = 2 THEN 0.25 ELSE 0.875 END");
    }
    {
        auto connection = db::open_database(camp / "target" / "sum" / "seed-2.db", db::OpenMode::read_write);
        connection.exec("UPDATE individual SET r_max = 0.75");
    }
    auto connection = db::open_database(camp / "target" / "mo" / "seed-1.db", db::OpenMode::read_write);
    connection.exec(
        "UPDATE individual SET balls = CASE WHEN id IN (SELECT id FROM individual ORDER BY id LIMIT 3) "
        "THEN 2 ELSE 0 END");
}

}  // namespace

TEST_CASE("stats on a campaign: success counts, quartiles and tests by hand", "[runs][stats][cli]") {
    test::TempDir dir;
    const auto camp = dir / "camp";
    test::copy_tiny_campaign(camp, 2);
    set_hand_bests(camp);
    set_hand_signal(camp);
    const auto result =
        test::run_cli({"stats", camp.string(), "--runs-csv", (dir / "runs.csv").string(), "--tests-csv",
                       (dir / "tests.csv").string(), "--csv", (dir / "success.csv").string()});
    INFO(result.err);
    REQUIRE(result.exit_code == 0);

    const auto runs = test::read_file(dir / "runs.csv");
    CHECK_THAT(runs,
               Contains("treatment,seed,generation,best_reward,success,policies,ball_policies,mean_r_max\n"));
    // population 8: generation 0 evaluates 2 x 8 (ea.initial_multiplier), generations 1 and 2 eight
    // children each, so 32 policies; mean r_max over generations 0-2 (the window of 10 reaches
    // back to 0): sum seed 1 (24 x 0.875 + 8 x 0.25) / 32 = 0.71875, seed 2 0.75
    CHECK_THAT(runs, Contains("none,1,2,0.125,0,32,0,\n") && Contains("sum,2,2,0.75,1,32,0,0.75\n") &&
                         Contains("mo-rand,2,2,0.5,1,32,0,"));
    CHECK_THAT(runs, Contains("sum,1,2,0.625,1,32,0,0.71875\n") && Contains("mo,1,2,0.375,0,32,3,"));
    // the text: sum's r_max is the mean of its runs' (0.71875 + 0.75) / 2 = 0.734375 (%.4g: 0.7344),
    // none has no KB, mo's 3 ball-collecting policies are counted
    CHECK_THAT(result.out, Contains("none              -           64          0\n") &&
                               Contains("sum          0.7344           64          0\n") &&
                               Contains("mo  ") && Contains("64          3\n"));
    // --signal-window 1: generation 2 alone, so sum's runs give 0.25 and 0.75
    const auto last = test::run_cli({"stats", camp.string(), "--signal-window", "1"});
    REQUIRE(last.exit_code == 0);
    CHECK_THAT(last.out,
               Contains("mean r_max of generations 2-2") && Contains("sum             0.5           64"));
    // the table says its r_max are the stored, raw averages (the report's figure divides them)
    CHECK_THAT(last.out, Contains("raw averages, not divided by the KB's largest"));
    const auto bad = test::run_cli({"stats", camp.string(), "--signal-window", "0"});
    CHECK(bad.exit_code == 2);
    CHECK_THAT(bad.err, Contains("--signal-window must be >= 1, got 0"));
    // success (>= 0.5) by generation: every generation holds the same best here
    CHECK(test::read_file(dir / "success.csv") ==
          "generation,none,sum,mo,sum-rand,mo-rand\n0,0,2,1,0,1\n1,0,2,1,0,1\n2,0,2,1,0,1\n");

    const auto tests = test::read_file(dir / "tests.csv");
    CHECK_THAT(tests, Contains("treatment_a,treatment_b,n_a,n_b,u,p,p_holm,a12,method,p_auto,p_se\n"));
    // 2 runs an arm: every p is the permutation p (SciPy's exact p where no value ties)
    // none {0.125, 0.25} vs sum {0.625, 0.75}: U = 0, no ties: p = 2 x 1/C(4,2) = 1/3; A12 = 0
    CHECK_THAT(tests, Contains("none,sum,2,2,0,0.333333333333333"));
    // none vs mo {0.375, 0.875}: U = 0 again
    CHECK_THAT(tests, Contains("none,mo,2,2,0,0.333333333333333"));
    // sum vs mo: 0.625 > 0.375, 0.75 > 0.375, the others lose: U = 2 = n_a n_b / 2, p = 1, A12 = 0.5
    CHECK_THAT(tests, Contains("sum,mo,2,2,2,1,1,0.5,permutation,1,\n"));
    // sum-rand {0, 0} vs mo-rand {0, 0.5}: U = 2 x 0.5 = 1 (each 0 ties with mo-rand's 0). Permutation:
    // mid-ranks 2, 2 | 2, 4, sum-rand's rank sum 4 against a mean of 5; the 6 relabellings give 4
    // (3 ways) or 6 (3 ways), all as far from 5: p = 1. The normal approximation (p_auto): U_b = 3,
    // tie term t = 3 zeros: sigma^2 = 4/12 (5 - (27 - 3)/(4 x 3)) = 1, z = (3 - 2 - 0.5) / 1 = 0.5,
    // p = erfc(0.5 / sqrt 2) = 0.6170750774519738 (Python's math.erfc)
    CHECK_THAT(tests, Contains("sum-rand,mo-rand,2,2,1,1,1,0.25,permutation,0.61707507745197"));
    CHECK_THAT(result.out, Contains("sum            2        2"));
}

TEST_CASE("stats --available compares the runs that have reached the generation and lists the others",
          "[runs][stats][cli]") {
    test::TempDir dir;
    const auto camp = dir / "camp";
    test::copy_tiny_campaign(camp, 2);
    set_hand_bests(camp);
    // as a running campaign leaves them: one run not started, one at generation 0 of 2
    std::filesystem::remove(camp / "target" / "mo" / "seed-2.db");
    {
        auto connection = db::open_database(camp / "target" / "sum" / "seed-1.db", db::OpenMode::read_write);
        connection.exec("DELETE FROM generation WHERE generation > 0");
    }
    REQUIRE(test::run_cli({"stats", camp.string()}).exit_code == 1);  // without the flag: refused

    const auto result =
        test::run_cli({"stats", camp.string(), "--available", "--runs-csv", (dir / "runs.csv").string(),
                       "--tests-csv", (dir / "tests.csv").string()});
    INFO(result.err);
    REQUIRE(result.exit_code == 0);
    CHECK_THAT(result.out, Contains("2 target runs not yet at generation 2 left out") &&
                               Contains("target/sum/seed-1.db") && Contains("target/mo/seed-2.db"));
    const auto runs = test::read_file(dir / "runs.csv");
    CHECK(std::count(runs.begin(), runs.end(), '\n') == 1 + 8);
    CHECK_THAT(runs, Contains("sum,2,2,0.75,1,32,") && Contains("mo,1,2,0.375,0,32,"));
    CHECK_THAT(runs, !Contains("sum,1,") && !Contains("mo,2,"));
    // none {0.125, 0.25} vs sum {0.75}: U = 0, exact p = 2 x 1/C(3,1) = 2/3
    const auto tests = test::read_file(dir / "tests.csv");
    CHECK_THAT(tests, Contains("none,sum,2,1,0,0.66666666666666"));

    // generation 2 is the last the runs are asked for; 0 reached by every started run
    const auto beyond = test::run_cli({"stats", camp.string(), "--available", "--generation", "7"});
    CHECK(beyond.exit_code == 2);
    CHECK(beyond.err_lines().size() == 1);
    CHECK_THAT(beyond.err,
               Contains("--generation 7 is beyond the 2 generations") && Contains("use --generation 2"));
    // every run back at generation 0: none has reached 1 yet
    for (const auto& entry : std::filesystem::recursive_directory_iterator(camp / "target")) {
        if (entry.path().extension() != ".db") continue;
        auto connection = db::open_database(entry.path(), db::OpenMode::read_write);
        connection.exec("DELETE FROM generation WHERE generation > 0");
    }
    const auto none_reached = test::run_cli({"stats", camp.string(), "--available", "--generation", "1"});
    CHECK(none_reached.exit_code == 1);
    CHECK(none_reached.err_lines().size() == 1);
    CHECK_THAT(none_reached.err, Contains("no target run has reached generation 1 yet"));
}

TEST_CASE("stats reports a missing, corrupt or unfinished run file", "[runs][stats][cli][errors]") {
    test::TempDir dir;
    const auto camp = dir / "camp";
    test::copy_tiny_campaign(camp, 2);

    SECTION("threshold outside [0, 1]") {
        const auto result = test::run_cli({"stats", camp.string(), "--threshold", "1.5"});
        CHECK(result.exit_code == 2);
        CHECK(result.err_lines().size() == 1);
        CHECK_THAT(result.err, Contains("--threshold must be within [0, 1]"));
    }
    SECTION("a generation beyond the runs' last") {
        // resuming cannot reach it: a usage error naming the last one
        const auto result = test::run_cli({"stats", camp.string(), "--generation", "5"});
        CHECK(result.exit_code == 2);
        CHECK(result.err_lines().size() == 1);
        CHECK_THAT(result.err,
                   Contains("--generation 5 is beyond the 2 generations") && Contains("use --generation 2"));
    }
    SECTION("a generation an unfinished run has not reached") {
        {
            auto connection =
                db::open_database(camp / "target" / "sum" / "seed-1.db", db::OpenMode::read_write);
            connection.exec("DELETE FROM generation WHERE generation > 0");
        }
        const auto result = test::run_cli({"stats", camp.string(), "--generation", "2"});
        CHECK(result.exit_code == 1);
        CHECK_THAT(result.err, Contains("has reached generation 0 of 2") && Contains("resume the campaign"));
    }
    SECTION("a missing run file") {
        std::filesystem::remove(camp / "target" / "mo" / "seed-2.db");
        const auto result = test::run_cli({"stats", camp.string()});
        CHECK(result.exit_code == 1);
        CHECK(result.err_lines().size() == 1);
        CHECK_THAT(result.err, Contains("target/mo/seed-2.db") && Contains("missing"));
    }
    SECTION("a corrupt run file") {
        test::write_file(camp / "target" / "sum" / "seed-1.db", std::string(4096, 'x'));
        const auto result = test::run_cli({"stats", camp.string()});
        CHECK(result.exit_code == 1);
        CHECK(result.err_lines().size() == 1);
        CHECK_THAT(result.err, Contains("seed-1.db"));
    }
    SECTION("a run file swapped with another") {
        std::filesystem::copy_file(camp / "target" / "sum" / "seed-1.db",
                                   camp / "target" / "mo" / "seed-1.db",
                                   std::filesystem::copy_options::overwrite_existing);
        const auto result = test::run_cli({"stats", camp.string()});
        CHECK(result.exit_code == 1);
        CHECK_THAT(result.err, Contains("campaign.db expects seed 1 treatment mo"));
    }
}
