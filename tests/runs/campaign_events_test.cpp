// stepstone stats' time-to-event statistics on a tiny campaign whose
// milestones are set by hand: the events CSV row by row, the log-rank test
// worked by hand and recomputed by statsmodels (scripts/logrank-check), and
// the errors for an unknown milestone and for runs without milestones
// (lib/runs/campaign_events.cpp, through campaign_stats).

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <sstream>

#include "runs/events_campaign.hpp"
#include "support/db_files.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;

TEST_CASE("stats: first events per run, Kaplan-Meier medians and the log-rank test by hand",
          "[runs][stats][events][cli]") {
    runstest::EventsCampaign c;
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
    "[runs][stats][events][cli][errors]") {
    runstest::EventsCampaign c;
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
