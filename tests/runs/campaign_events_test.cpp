// stepstone stats' time-to-event statistics on a tiny campaign whose
// milestones are set by hand: the events CSV row by row, the log-rank test and
// the Cox hazard ratio worked by hand and recomputed by statsmodels
// (scripts/logrank-check, scripts/hazard-check), and
// the errors for an unknown milestone and for runs without milestones
// (lib/runs/campaign_events.cpp, through campaign_stats).

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <vector>

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
    const auto hazard = c.dir / "hazard.csv";
    const auto result = test::run_cli({"stats", c.camp.string(), "--events-csv", events.string(),
                                       "--logrank-csv", logrank.string(), "--hazard-csv", hazard.string()});
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

    // the Cox model, no tied events (Breslow = Efron): with w = e^beta (beta the log HR of none to sum),
    // the at-risk counts above give the score U = 1 - (3w/(3w+3) + 3w/(3w+2) + 3w/(3w+1) + 2w/(2w+1)),
    // 0 at the estimate, and the information I = sum p(1 - p) over those four shares p, se = 1 / sqrt(I).
    // RMST up to 4: none 3 + 2/3 (S = 1 on [0, 3), 2/3 on [3, 4]), sum 2/3 + 3 * 1/3 = 5/3
    const std::string h = test::read_file(hazard);
    CHECK(
        h.rfind("treatment_a,treatment_b,event,n_a,n_b,events_a,events_b,hazard_ratio,ci_low,ci_high,log_hr,"
                "se,p_wald,score_chi2,p_score,ties,rmst_a,rmst_b,rmst_difference,horizon,note\n",
                0) == 0);
    CHECK(std::count(h.begin(), h.end(), '\n') == 1 + 4);  // one pair, four milestones
    const std::string hazard_prefix = "none,sum,pickup,3,3,1,3,";
    const auto hazard_row = h.find(hazard_prefix);
    REQUIRE(hazard_row != std::string::npos);
    std::vector<std::string> f;
    std::istringstream hazard_fields(h.substr(hazard_row, h.find('\n', hazard_row) - hazard_row));
    for (std::string field; std::getline(hazard_fields, field, ',');) f.push_back(field);
    REQUIRE(f.size() == 20);  // the empty note is the 21st field
    const double beta = std::stod(f[10]), w = std::exp(beta);
    const double shares[] = {3 * w / (3 * w + 3), 3 * w / (3 * w + 2), 3 * w / (3 * w + 1),
                             2 * w / (2 * w + 1)};
    double score = 1, information = 0;
    for (double share : shares) {
        score -= share;
        information += share * (1 - share);
    }
    CHECK(std::abs(score) < 1e-10);
    CHECK(beta < 0);  // none reaches the pickup later: a lower hazard than sum
    CHECK(std::stod(f[7]) == Approx(w).epsilon(1e-12));
    CHECK(std::stod(f[11]) == Approx(1 / std::sqrt(information)).epsilon(1e-9));
    CHECK(std::stod(f[8]) ==
          Approx(std::exp(beta - 1.959963984540054 / std::sqrt(information))).epsilon(1e-9));
    CHECK(f[15] == "efron");
    CHECK(std::stod(f[16]) == Approx(3 + 2.0 / 3).epsilon(1e-12));
    CHECK(std::stod(f[17]) == Approx(5.0 / 3).epsilon(1e-12));
    CHECK(std::stod(f[18]) == Approx(2).epsilon(1e-12));
    CHECK(f[19] == "4");
    // no ball in none: the MLE runs to HR 0, no numbers; no release at all
    CHECK_THAT(h, Contains("none,sum,ball,3,3,0,1,,,,,,,") && Contains(",no events in none (HR -> 0)\n"));
    CHECK_THAT(h, Contains("none,sum,release,3,3,0,0,,,,,,,0,1,efron,4,4,0,4,no events in either arm\n"));

    // the text: the default milestone is the pickup; KM medians none: S = 2/3 after 3, never below
    // 1/2, not reached; sum: S = 2/3 after 0, 1/3 after 1: median 1; the RMSTs above
    CHECK_THAT(result.out, Contains("time to first pickup"));
    CHECK_THAT(result.out, Contains("none           3        1              not reached        3.667\n") &&
                               Contains("sum            3        3                        1        1.667\n"));
    char hr_text[96];
    std::snprintf(hr_text, sizeof hr_text, "         2  %.3g [%.3g, %.3g]\n", std::stod(f[7]),
                  std::stod(f[8]), std::stod(f[9]));
    CHECK_THAT(result.out, Contains("RMST a-b  HR [95% CI]\n") && Contains(hr_text));
    // the Mann-Whitney p of 3 runs an arm is the permutation p
    CHECK_THAT(result.out, Contains("permutation"));

    // statsmodels recomputes the log-rank CSV from the events CSV
    const auto check =
        test::run_program({"/usr/bin/python3", std::string(STEPSTONE_SOURCE_DIR) + "/scripts/logrank-check",
                           events.string(), logrank.string()});
    INFO(check.out << check.err);
    CHECK(check.exit_code == 0);
    CHECK_THAT(check.out, Contains("ok   none vs sum pickup"));
    // and the hazard CSV, with PHReg
    const auto hazard_check =
        test::run_program({"/usr/bin/python3", std::string(STEPSTONE_SOURCE_DIR) + "/scripts/hazard-check",
                           events.string(), hazard.string()});
    INFO(hazard_check.out << hazard_check.err);
    CHECK(hazard_check.exit_code == 0);
    CHECK_THAT(hazard_check.out, Contains("ok   none vs sum pickup (efron)") &&
                                     Contains("ok   none vs sum ball (efron): not estimable"));

    const auto ball = test::run_cli({"stats", c.camp.string(), "--event", "ball"});
    REQUIRE(ball.exit_code == 0);
    CHECK_THAT(ball.out, Contains("time to first ball") &&
                             Contains("sum            3        1              not reached            4\n") &&
                             Contains("  not estimable: no events in none (HR -> 0)\n"));
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
    const auto hazard = c.dir / "hazard.csv";
    const auto no_hazard = test::run_cli({"stats", c.camp.string(), "--hazard-csv", hazard.string()});
    CHECK(no_hazard.exit_code == 1);
    CHECK(no_hazard.err_lines().size() == 1);
    CHECK_THAT(no_hazard.err, Contains("1 of 6 target runs do not record milestones"));
    CHECK_FALSE(std::filesystem::exists(hazard));

    // without them, the older file is read as it is and the text says why the events are missing
    const auto plain = test::run_cli({"stats", c.camp.string(), "--runs-csv", runs.string()});
    INFO(plain.err);
    CHECK(plain.exit_code == 0);
    CHECK_THAT(plain.out, Contains("milestones: not recorded by 1 of 6 target runs"));
    CHECK(std::filesystem::exists(runs));
}
