// stepstone stats' time-to-event statistics on a tiny campaign whose
// milestones are set by hand: the events CSV row by row, the log-rank test
// worked by hand and recomputed by statsmodels (scripts/logrank-check), and
// the errors for an unknown milestone and for runs without milestones.

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <sstream>

#include "db/database.hpp"
#include "support/db_files.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;

namespace {

// the shipped KB fixture, then none and sum x 3 seeds x 4 generations, population 8
std::string campaign_json() {
    return std::string(R"({
  "kb": {"file": ")") +
           STEPSTONE_SOURCE_DIR + R"(/examples/fixtures/demo_kb.db.gz"},
  "randomize_seed": 1,
  "target": {
    "config": {"task": {"kind": "target", "steps_per_start": 200, "starts": 1}, "ea": {"population_size": 8}},
    "runs": 3, "generations": 4, "treatments": ["none", "sum"]
  }
})";
}

// the first generation of each milestone set by hand: every individual's
// milestones cleared, then one individual of generation g given the milestone
void set_first(const std::filesystem::path& run, const std::map<std::string, int>& first) {
    auto connection = db::open_database(run, db::OpenMode::read_write);
    connection.exec(
        "UPDATE individual SET presses = 0, pickups = 0, carry_steps = 0, basket_releases = 0, balls = 0");
    const std::map<std::string, std::string> column = {
        {"press", "presses"}, {"pickup", "pickups"}, {"release", "basket_releases"}, {"ball", "balls"}};
    for (const auto& [event, generation] : first) {
        connection.exec("UPDATE individual SET " + column.at(event) +
                        " = 2 WHERE id = (SELECT min(id) FROM " +
                        "individual WHERE generation = " + std::to_string(generation) + ")");
    }
}

struct Campaign {
    test::TempDir dir;
    std::filesystem::path camp = dir / "camp";
    Campaign() {
        test::write_file(dir / "c.json", campaign_json());
        const auto made =
            test::run_cli({"campaign", (dir / "c.json").string(), "--dir", camp.string(), "--quiet"});
        INFO(made.err);
        REQUIRE(made.exit_code == 0);
        // pickups: none at 3, never, never; sum at 0, 1, 4. Presses at 0 everywhere; no release or ball but
        // one
        for (int seed = 1; seed <= 3; ++seed) {
            std::map<std::string, int> none{{"press", 0}}, sum{{"press", 0}};
            if (seed == 1) none["pickup"] = 3;
            sum["pickup"] = seed == 1 ? 0 : seed == 2 ? 1 : 4;
            if (seed == 3) sum["ball"] = 4;
            set_first(camp / "target" / "none" / ("seed-" + std::to_string(seed) + ".db"), none);
            set_first(camp / "target" / "sum" / ("seed-" + std::to_string(seed) + ".db"), sum);
        }
    }
};

}  // namespace

TEST_CASE("stats: first events per run, Kaplan-Meier medians and the log-rank test by hand",
          "[exp][stats][events][cli]") {
    Campaign c;
    const auto events = c.dir / "events.csv";
    const auto logrank = c.dir / "logrank.csv";
    const auto result = test::run_cli(
        {"stats", c.camp.string(), "--events-csv", events.string(), "--logrank-csv", logrank.string()});
    INFO(result.err);
    REQUIRE(result.exit_code == 0);

    const std::string e = test::read_file(events);
    CHECK(e.rfind("treatment,seed,event,generation,observed\n", 0) == 0);
    CHECK_THAT(e, Contains("none,1,pickup,3,1\n") && Contains("none,2,pickup,4,0\n") &&
                      Contains("none,3,pickup,4,0\n"));
    CHECK_THAT(e, Contains("sum,1,pickup,0,1\n") && Contains("sum,2,pickup,1,1\n") &&
                      Contains("sum,3,pickup,4,1\n"));
    CHECK_THAT(
        e, Contains("sum,3,ball,4,1\n") && Contains("none,1,release,4,0\n") && Contains("sum,2,press,0,1\n"));
    CHECK(std::count(e.begin(), e.end(), '\n') == 1 + 6 * 4);

    // none {3, 4+, 4+} against sum {0, 1, 4}, at each event time (n at risk, n_none, d):
    // 0: (6, 3, 1) E += 1/2, V += 1/4;  1: (5, 3, 1) E += 3/5, V += 6/25;
    // 3: (4, 3, 1) E += 3/4, V += 3/16;  4: (3, 2, 1) E += 2/3, V += 2/9 (the censored runs are at risk at 4)
    const double expected = 0.5 + 0.6 + 0.75 + 2.0 / 3.0;
    const double variance = 0.25 + 0.24 + 0.1875 + 2.0 / 9.0;
    const double chi2 = (1 - expected) * (1 - expected) / variance;
    const double p = std::erfc(std::sqrt(chi2 / 2));
    const std::string l = test::read_file(logrank);
    CHECK(l.rfind("treatment_a,treatment_b,event,n_a,n_b,events_a,events_b,chi2,p,p_holm\n", 0) == 0);
    const std::string prefix = "none,sum,pickup,3,3,1,3,";
    const auto row = l.find(prefix);
    REQUIRE(row != std::string::npos);
    // chi2,p,p_holm after the prefix
    std::istringstream fields(l.substr(row + prefix.size(), l.find('\n', row) - row - prefix.size()));
    std::string chi2_text, p_text;
    std::getline(fields, chi2_text, ',');
    std::getline(fields, p_text, ',');
    CHECK(std::stod(chi2_text) == Approx(chi2).epsilon(1e-12));
    CHECK(std::stod(p_text) == Approx(p).epsilon(1e-12));

    // the text: the default milestone is the pickup; KM medians none: S = 2/3 after 3, never below
    // 1/2, not reached; sum: S = 2/3 after 0, 1/3 after 1: median 1
    CHECK_THAT(result.out, Contains("time to first pickup"));
    CHECK_THAT(result.out, Contains("none           3        1    not reached\n") &&
                               Contains("sum            3        3              1\n"));
    // the Mann-Whitney p of 3 runs an arm is the permutation p
    CHECK_THAT(result.out, Contains("permutation"));

    // statsmodels recomputes the log-rank CSV from the events CSV
    const auto check =
        test::run_program({"/usr/bin/python3", std::string(STEPSTONE_SOURCE_DIR) + "/scripts/logrank-check",
                           events.string(), logrank.string()});
    INFO(check.out << check.err);
    CHECK(check.exit_code == 0);
    CHECK_THAT(check.out, Contains("ok   none vs sum pickup"));

    const auto ball = test::run_cli({"stats", c.camp.string(), "--event", "ball"});
    REQUIRE(ball.exit_code == 0);
    CHECK_THAT(ball.out,
               Contains("time to first ball") && Contains("sum            3        1    not reached\n"));
}

TEST_CASE(
    "stats refuses an unknown milestone and time-to-event outputs of runs without milestones, writing "
    "nothing",
    "[exp][stats][events][cli][errors]") {
    Campaign c;
    const auto events = c.dir / "events.csv";
    const auto runs = c.dir / "runs.csv";
    const auto unknown =
        test::run_cli({"stats", c.camp.string(), "--event", "carry", "--events-csv", events.string()});
    CHECK(unknown.exit_code == 2);
    CHECK(unknown.err_lines().size() == 1);
    CHECK_THAT(unknown.err,
               Contains("--event: unknown milestone 'carry' (one of press, pickup, release, ball)"));
    CHECK_FALSE(std::filesystem::exists(events));

    test::make_schema4_run(c.camp / "target" / "sum" / "seed-2.db");  // one run file as schema 4 left it
    const auto refused = test::run_cli(
        {"stats", c.camp.string(), "--runs-csv", runs.string(), "--events-csv", events.string()});
    CHECK(refused.exit_code == 1);
    CHECK(refused.err_lines().size() == 1);
    CHECK_THAT(refused.err,
               Contains("1 of 6 target runs do not record milestones") && Contains("target/sum/seed-2.db"));
    CHECK_FALSE(std::filesystem::exists(events));
    CHECK_FALSE(std::filesystem::exists(runs));

    // without them, the older file is read as it is and the text says why the events are missing
    const auto plain = test::run_cli({"stats", c.camp.string(), "--runs-csv", runs.string()});
    INFO(plain.err);
    CHECK(plain.exit_code == 0);
    CHECK_THAT(plain.out, Contains("milestones: not recorded by 1 of 6 target runs"));
    CHECK(std::filesystem::exists(runs));
}

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

TEST_CASE("pool: a campaign's CSVs split in two overlapping halves pool back to the whole campaign's tests",
          "[exp][stats][events][cli][pool]") {
    Campaign c;
    const std::filesystem::path d = c.dir.path();
    const auto whole =
        test::run_cli({"stats", c.camp.string(), "--runs-csv", (d / "runs.csv").string(), "--events-csv",
                       (d / "events.csv").string(), "--tests-csv", (d / "tests.csv").string(),
                       "--logrank-csv", (d / "logrank.csv").string()});
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
    for (const char* out : {"runs", "events", "tests", "logrank"}) {
        args.push_back(std::string("--") + out + "-csv");
        args.push_back((d / (std::string("p_") + out + ".csv")).string());
    }
    args.insert(args.end(), {"--kaplan-meier", (d / "km.png").string()});
    const auto pooled = test::run_cli(args);
    INFO(pooled.err);
    REQUIRE(pooled.exit_code == 0);
    // the oracle: stepstone stats of the whole campaign, byte for byte (the tests it makes are checked by
    // hand and by statsmodels above)
    for (const char* out : {"runs", "events", "tests", "logrank"}) {
        INFO(out);
        CHECK(test::read_file(d / (std::string("p_") + out + ".csv")) ==
              test::read_file(d / (std::string(out) + ".csv")));
    }
    CHECK_THAT(pooled.out,
               Contains("pooled: 6 runs at generation 4") &&
                   Contains("2 runs found in more than one input, identical in each: none/2 sum/2"));
    CHECK_THAT(pooled.out, Contains("none           3        1    not reached\n") &&
                               Contains("sum            3        3              1\n"));
    CHECK(test::read_file(d / "km.png").rfind("\x89PNG", 0) == 0);

    // outputs exist: refused without --force, nothing replaced
    const auto again = test::run_cli(args);
    CHECK(again.exit_code != 0);
    CHECK(again.err_lines().size() == 1);
    CHECK(test::read_file(d / "p_runs.csv") == runs);
}

TEST_CASE("pool refuses inputs that disagree, lack their events or mix generations, in one line",
          "[exp][stats][events][cli][pool][errors]") {
    Campaign c;
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
