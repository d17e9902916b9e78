// stepstone pool: the statistics of runs pooled from several campaigns' CSVs
// (lib/runs/pooled_stats.cpp). Two tiny hand-written inputs are pooled in
// process, their counts and success rates worked out by hand; the oracle of
// the CLI cases is stepstone stats of the whole campaign, whose tests
// campaign_events_test.cpp checks by hand.
#include "runs/pooled_stats.hpp"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <sstream>

#include "runs/events_campaign.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;

namespace {

// the lines of a CSV whose seed (second field) is in `seeds`, under its header
std::string rows_of_seeds(const std::string& csv, std::initializer_list<int> seeds) {
    std::istringstream in(csv);
    std::string line, out;
    std::getline(in, line);
    out = line + "\n";
    while (std::getline(in, line)) {
        const auto comma = line.find(',');
        const int seed = std::stoi(line.substr(comma + 1));
        if (std::find(seeds.begin(), seeds.end(), seed) != seeds.end()) out += line + "\n";
    }
    return out;
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
    const auto at = text.find(from);
    REQUIRE(at != std::string::npos);
    return text.replace(at, from.size(), to);
}

}  // namespace

TEST_CASE("two hand-written runs CSVs and events CSVs pool to the counts and success rates worked by hand",
          "[runs][pool]") {
    test::TempDir dir;
    const std::string header =
        "treatment,seed,generation,best_reward,success,policies,ball_policies,mean_r_max\n";
    // machine A ran seed 1, machine B seed 2 and sum seed 1 again (the same row); B exported none
    // seed 2 with another threshold (its success column says 0)
    test::write_file(dir / "a_runs.csv", header + "none,1,10,0.25,0,100,0,\nsum,1,10,0.75,1,100,4,0.5\n");
    test::write_file(
        dir / "b_runs.csv",
        header + "none,2,10,0.5,0,90,1,\nsum,2,10,0.125,0,80,0,0.25\nsum,1,10,0.75,1,100,4,0.5\n");
    const std::string events = "treatment,seed,event,generation,observed\n";
    test::write_file(dir / "a_events.csv", events +
                                               "none,1,press,2,1\nnone,1,pickup,10,0\nnone,1,release,10,0\n"
                                               "none,1,ball,10,0\nsum,1,press,1,1\nsum,1,pickup,3,1\n"
                                               "sum,1,release,5,1\nsum,1,ball,10,0\n");
    test::write_file(dir / "b_events.csv", events +
                                               "none,2,press,0,1\nnone,2,pickup,7,1\nnone,2,release,10,0\n"
                                               "none,2,ball,10,0\nsum,2,press,10,0\nsum,2,pickup,10,0\n"
                                               "sum,2,release,10,0\nsum,2,ball,10,0\n");
    const std::vector<std::filesystem::path> runs_files{dir / "a_runs.csv", dir / "b_runs.csv"};
    const std::vector<std::filesystem::path> events_files{dir / "a_events.csv", dir / "b_events.csv"};
    const auto pooled = runs::pool_stats(runs_files, events_files, 0.5);

    CHECK(pooled.generation == 10);
    // seed-major, then the treatments in their order of first appearance
    REQUIRE(pooled.runs.size() == 4);
    const std::vector<std::pair<runs::Treatment, std::uint64_t>> order{{runs::Treatment::none, 1},
                                                                       {runs::Treatment::sum, 1},
                                                                       {runs::Treatment::none, 2},
                                                                       {runs::Treatment::sum, 2}};
    // success = best >= 0.5, whatever the CSV's success column said: 0.25 no, 0.75 yes, 0.5 yes, 0.125 no
    const std::vector<bool> success{false, true, true, false};
    for (std::size_t k = 0; k < 4; ++k) {
        CHECK(pooled.runs[k].treatment == order[k].first);
        CHECK(pooled.runs[k].seed == order[k].second);
        CHECK(pooled.runs[k].success == success[k]);
    }
    // none {0.25, 0.5} has 1 success, sum {0.75, 0.125} has 1
    REQUIRE(pooled.treatments.size() == 2);
    const auto& none = pooled.treatments[0];
    const auto& sum = pooled.treatments[1];
    CHECK(none.treatment == runs::Treatment::none);
    CHECK(none.best == std::vector<double>{0.25, 0.5});
    CHECK(none.successes == 1);
    CHECK(none.policies == 190);
    CHECK(none.ball_policies == 1);
    CHECK_FALSE(none.mean_r_max);
    CHECK(sum.best == std::vector<double>{0.75, 0.125});
    CHECK(sum.successes == 1);
    CHECK(sum.policies == 180);
    CHECK(sum.ball_policies == 4);
    REQUIRE(sum.mean_r_max);
    CHECK(*sum.mean_r_max == 0.375);  // (0.5 + 0.25) / 2
    // at threshold 0.75 only sum seed 1 succeeds
    const auto strict = runs::pool_stats(runs_files, events_files, 0.75);
    CHECK(strict.treatments[0].successes == 0);
    CHECK(strict.treatments[1].successes == 1);
    // sum seed 1, in both runs CSVs
    REQUIRE(pooled.repeated.size() == 1);
    CHECK(pooled.repeated[0].treatment == runs::Treatment::sum);
    CHECK(pooled.repeated[0].seed == 1);
    CHECK(pooled.repeated[0].files ==
          std::vector<std::string>{runs_files[0].string(), runs_files[1].string()});
    // first pickups: none {never, 7}, sum {3, never}: one run of each reached it by generation 10
    REQUIRE(pooled.run_events.size() == 4);
    CHECK(pooled.run_events[0].first[1] == std::nullopt);
    CHECK(pooled.run_events[1].first == runs::FirstEvents{1, 3, 5, std::nullopt});
    CHECK(pooled.run_events[2].first == runs::FirstEvents{0, 7, std::nullopt, std::nullopt});
    REQUIRE(pooled.events.summaries.size() == 8);  // 4 milestones x 2 treatments
    const auto& pickup_none = pooled.events.summaries[2];
    const auto& pickup_sum = pooled.events.summaries[3];
    CHECK(pickup_none.milestone == runs::Milestone::pickup);
    CHECK(pickup_none.treatment == runs::Treatment::none);
    CHECK(pickup_none.runs == 2);
    CHECK(pickup_none.reached == 1);
    CHECK(pickup_sum.treatment == runs::Treatment::sum);
    CHECK(pickup_sum.reached == 1);
    CHECK(pooled.events.summaries[0].reached == 2);  // both none runs pressed
    CHECK(pooled.events.summaries[1].reached == 1);  // sum seed 2 never did

    // the pickup's Cox model: sum's event at 3 with 2 + 2 runs at risk, none's at 7 with 2 none and 1 sum;
    // with w the HR of none to sum, the score 1 - w/(w+1) - 2w/(2w+1) is 0 where 2w^2 = 1, w = 1/sqrt 2,
    // where the shares w/(w+1) = sqrt 2 - 1 and 2w/(2w+1) = 2 - sqrt 2 give the information
    // 2 (sqrt 2 - 1)(2 - sqrt 2) = 6 sqrt 2 - 8
    const auto& pickup = pooled.events.tests[1];
    REQUIRE(pickup.milestone == runs::Milestone::pickup);
    REQUIRE(pickup.cox.estimate);
    CHECK(pickup.cox.estimate->hr == Approx(1 / std::sqrt(2.0)).epsilon(1e-12));
    CHECK(pickup.cox.estimate->se == Approx(1 / std::sqrt(6 * std::sqrt(2.0) - 8)).epsilon(1e-10));
    // RMST up to 10: none 7 + 3 / 2, sum 3 + 7 / 2; both curves end at 1/2: no strict median, survfit's
    // is the time S reached 1/2
    CHECK(pickup.rmst_a == Approx(8.5));
    CHECK(pickup.rmst_b == Approx(6.5));
    std::ostringstream text;
    runs::write_pooled_text(text, pooled, runs::Milestone::pickup);
    CHECK_THAT(text.str(),
               Contains("none           2        1 not reached (midpoint 7)          8.5\n") &&
                   Contains("sum            2        1 not reached (midpoint 3)          6.5\n") &&
                   Contains("         2  0.707 ["));
}

TEST_CASE("pool: a campaign's CSVs split in two overlapping halves pool back to the whole campaign's tests",
          "[runs][pool][cli]") {
    runstest::EventsCampaign c;
    const std::filesystem::path d = c.dir.path();
    const auto whole = test::run_cli(
        {"stats", c.camp.string(), "--runs-csv", (d / "runs.csv").string(), "--events-csv",
         (d / "events.csv").string(), "--tests-csv", (d / "tests.csv").string(), "--logrank-csv",
         (d / "logrank.csv").string(), "--hazard-csv", (d / "hazard.csv").string()});
    REQUIRE(whole.exit_code == 0);
    const std::string runs = test::read_file(d / "runs.csv"), events = test::read_file(d / "events.csv");
    // machine A finished seeds 1 and 2, machine B seeds 2 and 3: seed 2 is in both, identical
    test::write_file(d / "a_runs.csv", rows_of_seeds(runs, {1, 2}));
    test::write_file(d / "b_runs.csv", rows_of_seeds(runs, {2, 3}));
    test::write_file(d / "a_events.csv", rows_of_seeds(events, {1, 2}));
    test::write_file(d / "b_events.csv", rows_of_seeds(events, {2, 3}));
    const std::vector<std::string> inputs = {"pool",
                                             "--runs",
                                             (d / "a_runs.csv").string(),
                                             (d / "b_runs.csv").string(),
                                             "--events",
                                             (d / "a_events.csv").string(),
                                             (d / "b_events.csv").string()};
    auto args = inputs;
    for (const char* out : {"runs", "events", "tests", "logrank", "hazard"}) {
        args.push_back(std::string("--") + out + "-csv");
        args.push_back((d / (std::string("p_") + out + ".csv")).string());
    }
    args.insert(args.end(), {"--kaplan-meier", (d / "km.png").string()});
    const auto pooled = test::run_cli(args);
    INFO(pooled.err);
    REQUIRE(pooled.exit_code == 0);
    // the oracle: stepstone stats of the whole campaign, byte for byte (the tests it makes are checked by
    // hand and by statsmodels above)
    for (const char* out : {"runs", "events", "tests", "logrank", "hazard"}) {
        INFO(out);
        CHECK(test::read_file(d / (std::string("p_") + out + ".csv")) ==
              test::read_file(d / (std::string(out) + ".csv")));
    }
    CHECK_THAT(pooled.out,
               Contains("pooled: 6 runs at generation 4") &&
                   Contains("2 runs found in more than one input, identical in each: none/2 sum/2"));
    CHECK_THAT(pooled.out, Contains("none           3        1              not reached        3.667\n") &&
                               Contains("sum            3        3                        1        1.667\n"));
    CHECK(test::read_file(d / "km.png").rfind("\x89PNG", 0) == 0);

    // outputs exist: refused without --force, nothing replaced
    const auto again = test::run_cli(args);
    CHECK(again.exit_code != 0);
    CHECK(again.err_lines().size() == 1);
    CHECK(test::read_file(d / "p_runs.csv") == runs);
    // the hazard CSV alone, existing: the same one-line refusal; with --force it is replaced
    const std::vector<std::string> hazard_only = {inputs[0], inputs[1],      inputs[2],
                                                  inputs[3], inputs[4],      inputs[5],
                                                  inputs[6], "--hazard-csv", (d / "p_hazard.csv").string()};
    test::write_file(d / "p_hazard.csv", "old\n");
    const auto refused = test::run_cli(hazard_only);
    CHECK(refused.exit_code != 0);
    CHECK(refused.err_lines().size() == 1);
    CHECK_THAT(refused.err, Contains("p_hazard.csv"));
    CHECK(test::read_file(d / "p_hazard.csv") == "old\n");
    auto forced = hazard_only;
    forced.push_back("--force");
    REQUIRE(test::run_cli(forced).exit_code == 0);
    CHECK(test::read_file(d / "p_hazard.csv") == test::read_file(d / "hazard.csv"));
}

TEST_CASE("pool refuses inputs that disagree, lack their events or mix generations, in one line",
          "[runs][pool][cli][errors]") {
    runstest::EventsCampaign c;
    const std::filesystem::path d = c.dir.path();
    REQUIRE(test::run_cli({"stats", c.camp.string(), "--runs-csv", (d / "runs.csv").string(), "--events-csv",
                           (d / "events.csv").string()})
                .exit_code == 0);
    const std::string runs = test::read_file(d / "runs.csv"), events = test::read_file(d / "events.csv");
    const auto pool = [&](const std::string& runs_b, const std::string& events_b) {
        test::write_file(d / "b_runs.csv", runs_b);
        test::write_file(d / "b_events.csv", events_b);
        return test::run_cli({"pool", "--runs", (d / "runs.csv").string(), (d / "b_runs.csv").string(),
                              "--events", (d / "events.csv").string(), (d / "b_events.csv").string()});
    };
    const auto expect_error = [](const test::CliResult& r, const std::string& text) {
        INFO(r.err);
        CHECK(r.exit_code == 1);
        CHECK(r.err_lines().size() == 1);
        CHECK_THAT(r.err, Contains(text));
    };
    // the same run with another best reward, or another first pickup
    const std::string sum2 = rows_of_seeds(runs, {2});
    const auto best_at = sum2.find("sum,2,4,") + 8;
    std::string other_best = sum2;
    other_best.replace(best_at, sum2.find(',', best_at) - best_at, "0.99");
    expect_error(pool(other_best, rows_of_seeds(events, {2})), "disagree on run sum seed 2");
    expect_error(pool(rows_of_seeds(runs, {2}),
                      replaced(rows_of_seeds(events, {2}), "sum,2,pickup,1,1", "sum,2,pickup,2,1")),
                 "disagree on the events of run sum seed 2");
    // a run without events, events without a run
    test::write_file(d / "lone_runs.csv",
                     "treatment,seed,generation,best_reward,success,policies,ball_policies,"
                     "mean_r_max\nsum,9,4,0,0,40,0,0.5\n");
    const auto no_events = test::run_cli(
        {"pool", "--runs", (d / "lone_runs.csv").string(), "--events", (d / "events.csv").string()});
    expect_error(no_events, "run sum seed 9");
    // another generation: every row of seed 3 exported at generation 3
    std::string late_runs =
        replaced(replaced(rows_of_seeds(runs, {3}), "none,3,4,", "none,3,3,"), "sum,3,4,", "sum,3,3,");
    test::write_file(d / "b_runs.csv", late_runs);
    const auto mixed = test::run_cli({"pool", "--runs", (d / "runs.csv").string(),
                                      (d / "b_runs.csv").string(), "--events", (d / "events.csv").string()});
    expect_error(mixed, "disagree on run");  // seed 3 is in both: the generation differs
    test::write_file(d / "a_runs.csv", rows_of_seeds(runs, {1, 2}));
    const auto generations =
        test::run_cli({"pool", "--runs", (d / "a_runs.csv").string(), (d / "b_runs.csv").string(), "--events",
                       (d / "events.csv").string()});
    expect_error(generations, "different generations");
    // not a runs CSV, a field that is not a number
    expect_error(pool(events, events), "not the expected CSV");
    expect_error(pool(replaced(runs, "none,1,4,", "none,x,4,"), events), "seed 'x' is not a number");
}
