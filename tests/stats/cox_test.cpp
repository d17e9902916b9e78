// The Cox hazard ratio, the restricted mean time to event and the midpoint
// median against statsmodels 0.13.5 and R's survfit convention: the expected
// values come from tests/stats/hazard_oracle.py (PHReg with ties="breslow" and
// ties="efron", numpy's integral of SurvfuncRight's curve, survfit's median
// rule), pasted here; the last case recomputes every hazard ratio of E1's and
// E2's committed events CSVs (docs/results) and compares them with PHReg's,
// which the script wrote to tests/stats/hazard_results_expected.csv.

#include "stats/cox.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "stats/survival.hpp"

using namespace stepstone;
using namespace stepstone::stats;
using Catch::Matchers::Contains;

namespace {

struct CoxFixture {
    const char* name;
    Survival a, b;
    double horizon;                      // of the RMST
    CoxStatus status;                    // the same for both ties methods here
    std::vector<double> breslow, efron;  // log_hr, se, hr, ci_low, ci_high, Wald p; empty when not estimated
    std::optional<double> score_breslow, score_efron;  // statsmodels cannot build a model without events
    double rmst_a, rmst_b;
    std::optional<double> midpoint_a, midpoint_b;
};

const std::vector<CoxFixture>& cox_fixtures() {
    static const std::vector<CoxFixture> list = {
        {"ties_and_censoring",
         {{3, 5, 5, 8, 10, 10, 12}, {1, 1, 0, 1, 0, 1, 0}},
         {{2, 3, 3, 6, 7, 9, 11, 15}, {1, 1, 1, 0, 1, 1, 0, 1}},
         15,
         CoxStatus::estimated,
         {-0.3067680838947248, 0.6730207630935036, 0.7358212299145018, 0.19674151067229023, 2.752001245404421,
          0.6485282261755166},
         {-0.3248331616489644, 0.6728756655592216, 0.7226479089706784, 0.1932742272025015, 2.7019639809116516,
          0.6292706877595553},
         0.20936325043445178,
         0.23506993693545197,
         9.714285714285715,
         8.1875,
         10.0,
         7.0},
        {"no_events_in_a",
         {{10, 10, 10, 10}, {0, 0, 0, 0}},
         {{2, 4, 6, 10}, {1, 1, 1, 0}},
         10,
         CoxStatus::tends_to_zero,
         {},
         {},
         4.2126482213438745,
         4.2126482213438745,
         10.0,
         5.5,
         std::nullopt,
         5.0},
        {"generations_censored_at_500",
         {{0, 0, 12, 40, 500, 500, 500}, {1, 1, 1, 1, 0, 0, 0}},
         {{0, 300, 500, 500, 500, 500, 500}, {1, 1, 0, 0, 0, 0, 0}},
         500,
         CoxStatus::estimated,
         {0.916985291421775, 0.8729128104153919, 2.501737002024891, 0.4520816930538534, 13.844152779163597,
          0.293493353041577},
         {0.9425761088770757, 0.8719093129322648, 2.566584710934722, 0.46471324443427525, 14.175100790215422,
          0.2796756146168182},
         1.1790945280515184,
         1.2539917781102736,
         221.71428571428575,
         400.00000000000006,
         40.0,
         std::nullopt},
        {"all_events_tied_at_one_time",
         {{5, 5, 5, 8}, {1, 1, 1, 0}},
         {{5, 5, 8, 8}, {1, 1, 0, 0}},
         8,
         CoxStatus::estimated,
         {0.4054651081081645, 0.9128709291752769, 1.5000000000000002, 0.25064215469347034, 8.976941659122343,
          0.656923459709192},
         {0.5748799465147906, 0.9151649026124334, 1.776917189006846, 0.29558161052375165, 10.682108034370678,
          0.5298920012195112},
         0.2,
         0.4054172746774024,
         5.75,
         6.5,
         5.0,
         5.0},
        {"heavy_ties",
         {{1, 1, 2, 2, 2, 3, 4, 4, 6, 6, 6}, {1, 1, 1, 0, 1, 1, 1, 0, 1, 0, 0}},
         {{1, 2, 2, 3, 3, 3, 5, 5, 6, 6}, {1, 1, 1, 1, 1, 0, 1, 1, 0, 0}},
         6,
         CoxStatus::estimated,
         {0.00900635041325448, 0.5367779552347298, 1.009047029619153, 0.35237507752461966, 2.889466290112694,
          0.9866132900571672},
         {-0.014944326523198614, 0.5361652872453755, 0.9851667857365023, 0.34444908984657796,
          2.8176982443201934, 0.9777637531497413},
         0.00028152126158227224,
         0.0007768966464877256,
         3.8333333333333335,
         3.8499999999999996,
         4.0,
         4.0},
        {"no_events_in_b",
         {{1, 3, 3, 7}, {1, 1, 0, 1}},
         {{2, 5, 9}, {0, 0, 0}},
         9,
         CoxStatus::tends_to_infinity,
         {},
         {},
         2.401832824215496,
         2.4018328242154956,
         4.5,
         9.0,
         5.0,
         std::nullopt},
        {"no_events_at_all",
         {{4, 4}, {0, 0}},
         {{4, 4, 4}, {0, 0, 0}},
         4,
         CoxStatus::no_events,
         {},
         {},
         std::nullopt,
         std::nullopt,
         4.0,
         4.0,
         std::nullopt,
         std::nullopt},
        {"b_events_after_a_left",
         {{1, 2, 3}, {1, 1, 1}},
         {{10, 10, 12}, {1, 1, 0}},
         12,
         CoxStatus::tends_to_infinity,
         {},
         {},
         5.051660516605167,
         5.051660516605167,
         2.0,
         10.666666666666666,
         2.0,
         10.0},
        {"plateau_at_one_half",
         {{1, 2, 2, 4}, {1, 1, 0, 1}},
         {{2, 2, 5, 5}, {1, 1, 0, 0}},
         5,
         CoxStatus::estimated,
         {0.7211796225623804, 0.9182787367157396, 2.056858096355828, 0.3400666574821507, 12.440694009428368,
          0.43224237693994105},
         {0.6775698488732539, 0.9190225919750232, 1.969086734817113, 0.325080858446616, 11.927194322545569,
          0.46095680763020197},
         0.6430248943165807,
         0.5638469575766136,
         2.75,
         3.5,
         3.0,
         2.0},
        {"rmst_horizon_inside_the_curve",
         {{2, 4, 4, 9, 12}, {1, 1, 0, 1, 1}},
         {{1, 3, 6, 6, 8}, {1, 0, 1, 1, 1}},
         7,
         CoxStatus::estimated,
         {-0.7833994073223861, 0.8806997925138424, 0.45685034821811094, 0.08130568962079873,
          2.5670065851531585, 0.3737240893883296},
         {-0.8444022821608376, 0.876682237458033, 0.42981418905522745, 0.07709877450125206,
          2.3961501114418193, 0.3354574950006335},
         0.8282853837738622,
         0.9798962408985523,
         5.4,
         5.266666666666667,
         9.0,
         6.0},
    };
    return list;
}

// the estimate's numbers against PHReg's: 1e-9 relative (log_hr also absolute, for beta = 0)
void check_estimate(const CoxResult& r, const std::vector<double>& expected) {
    REQUIRE(r.estimate);
    REQUIRE(expected.size() == 6);
    const HazardRatio& e = *r.estimate;
    CHECK(e.log_hr == Approx(expected[0]).epsilon(1e-9).margin(1e-12));
    CHECK(e.se == Approx(expected[1]).epsilon(1e-9));
    CHECK(e.hr == Approx(expected[2]).epsilon(1e-9));
    CHECK(e.ci_low == Approx(expected[3]).epsilon(1e-9));
    CHECK(e.ci_high == Approx(expected[4]).epsilon(1e-9));
    CHECK(e.p == Approx(expected[5]).epsilon(1e-9));
}

void check_cox(const CoxResult& r, CoxStatus status, const std::vector<double>& expected,
               std::optional<double> score) {
    CHECK(r.status == status);
    if (status == CoxStatus::estimated) {
        check_estimate(r, expected);
    } else {
        CHECK_FALSE(r.estimate);
    }
    CHECK(r.score_chi2 == Approx(score.value_or(0.0)).epsilon(1e-9).margin(1e-12));
    CHECK(std::isfinite(r.score_p));
}

}  // namespace

TEST_CASE("Cox hazard ratio, CI and Wald p equal statsmodels' PHReg with Breslow and Efron ties",
          "[stats][cox]") {
    for (const auto& f : cox_fixtures()) {
        INFO(f.name);
        const CoxResult breslow = cox_hazard_ratio(f.a, f.b, Ties::breslow);
        const CoxResult efron = cox_hazard_ratio(f.a, f.b, Ties::efron);
        check_cox(breslow, f.status, f.breslow, f.score_breslow);
        check_cox(efron, f.status, f.efron, f.score_efron);
        CHECK(efron.ties == Ties::efron);
        CHECK(cox_hazard_ratio(f.a, f.b).ties == Ties::efron);  // the default
        const KaplanMeier a = kaplan_meier(f.a), b = kaplan_meier(f.b);
        CHECK(efron.events_a == a.events);
        CHECK(efron.events_b == b.events);
    }
}

TEST_CASE("swapping the samples inverts the hazard ratio and its CI", "[stats][cox]") {
    for (const auto& f : cox_fixtures()) {
        INFO(f.name);
        const CoxResult ab = cox_hazard_ratio(f.a, f.b);
        const CoxResult ba = cox_hazard_ratio(f.b, f.a);
        CHECK(ba.events_a == ab.events_b);
        CHECK(ba.score_chi2 == Approx(ab.score_chi2).epsilon(1e-12).margin(1e-15));
        if (ab.status == CoxStatus::tends_to_zero) CHECK(ba.status == CoxStatus::tends_to_infinity);
        if (ab.status == CoxStatus::tends_to_infinity) CHECK(ba.status == CoxStatus::tends_to_zero);
        if (ab.status != CoxStatus::estimated) continue;
        REQUIRE(ba.estimate);
        CHECK(ba.estimate->log_hr == Approx(-ab.estimate->log_hr).margin(1e-12));
        CHECK(ba.estimate->se == Approx(ab.estimate->se).epsilon(1e-10));
        CHECK(ba.estimate->ci_low == Approx(1.0 / ab.estimate->ci_high).epsilon(1e-10));
        CHECK(ba.estimate->p == Approx(ab.estimate->p).epsilon(1e-10));
    }
}

TEST_CASE("a hazard ratio without a finite estimate: a status, no numbers, no NaN", "[stats][cox]") {
    // a has no event: the likelihood rises as beta -> -inf (HR -> 0); b has none: HR -> inf
    const Survival none{{10, 10, 10}, {0, 0, 0}};
    const Survival some{{2, 4, 10}, {1, 1, 0}};
    CHECK(cox_hazard_ratio(none, some).status == CoxStatus::tends_to_zero);
    CHECK(cox_hazard_ratio(some, none).status == CoxStatus::tends_to_infinity);
    CHECK_FALSE(cox_hazard_ratio(none, some).estimate);
    // neither arm has an event
    const CoxResult nothing = cox_hazard_ratio(none, Survival{{3, 5}, {0, 0}});
    CHECK(nothing.status == CoxStatus::no_events);
    CHECK(nothing.score_chi2 == 0.0);
    CHECK(nothing.score_p == 1.0);
    // every event happens while only its own arm is at risk: a flat likelihood
    const CoxResult apart = cox_hazard_ratio(Survival{{5}, {1}}, Survival{{1}, {0}});
    CHECK(apart.status == CoxStatus::never_together);
    CHECK(apart.score_p == 1.0);
    // a's events all come after b's last subject left, though each arm has events: HR -> inf for b vs a
    const CoxResult late = cox_hazard_ratio(Survival{{10, 11}, {1, 1}}, Survival{{1, 2, 3}, {1, 1, 1}});
    CHECK(late.status == CoxStatus::tends_to_zero);
    CHECK(to_string(late.status) == "tends to 0");
    CHECK(to_string(Ties::breslow) == "breslow");
}

TEST_CASE("RMST: the area under the Kaplan-Meier curve up to the horizon, as numpy integrates it",
          "[stats][rmst]") {
    for (const auto& f : cox_fixtures()) {
        INFO(f.name);
        CHECK(restricted_mean(kaplan_meier(f.a), f.horizon) == Approx(f.rmst_a).epsilon(1e-12));
        CHECK(restricted_mean(kaplan_meier(f.b), f.horizon) == Approx(f.rmst_b).epsilon(1e-12));
    }
    // by hand: 1, 2 (event), 2 (censored), 4: S = 1 on [0, 1), 3/4 on [1, 2), 1/2 on [2, 4), 0 from 4
    const KaplanMeier km = kaplan_meier({{1, 2, 2, 4}, {1, 1, 0, 1}});
    CHECK(restricted_mean(km, 5) == Approx(1 + 0.75 + 2 * 0.5));
    CHECK(restricted_mean(km, 3) == Approx(1 + 0.75 + 0.5));
    CHECK(restricted_mean(km, 0.5) == 0.5);
    CHECK(restricted_mean(km, 0) == 0.0);
    // events at time 0 count from the start: S(0) is after them
    CHECK(restricted_mean(kaplan_meier({{0, 0, 4, 4}, {1, 1, 0, 0}}), 4) == Approx(2.0));
    CHECK_THROWS_WITH(restricted_mean(km, -1), Contains("horizon"));
    CHECK_THROWS_AS(restricted_mean(km, std::nan("")), DataError);
}

TEST_CASE("midpoint median: R's survfit convention where S sits at exactly 1/2, by hand",
          "[stats][survival]") {
    // 1, 2 (event), 2 (censored), 4: S = 3/4 after 1, 3/4 * 2/3 = 1/2 on [2, 4), 0 at 4. The strict
    // rule (first S < 1/2) gives 4; survfit sees S <= 1/2 from 2, exactly 1/2 until the next event
    // time 4, and takes (2 + 4) / 2 = 3
    const KaplanMeier plateau = kaplan_meier({{1, 2, 2, 4}, {1, 1, 0, 1}});
    CHECK(plateau.median == 4.0);
    CHECK(plateau.median_midpoint == 3.0);
    // S = 1/2 from 2 to the end (the last runs censored): the strict median is not reached; survfit
    // takes the time S reached 1/2, 2
    const KaplanMeier end = kaplan_meier({{2, 2, 5, 5}, {1, 1, 0, 0}});
    CHECK_FALSE(end.median);
    CHECK(end.median_midpoint == 2.0);
    // S jumps past 1/2: both rules agree
    const KaplanMeier jump = kaplan_meier({{1, 2, 3}, {1, 1, 1}});
    CHECK(jump.median == 2.0);
    CHECK(jump.median_midpoint == 2.0);
    // never at or below 1/2: neither exists
    CHECK_FALSE(kaplan_meier({{1, 5, 5}, {1, 0, 0}}).median_midpoint);
    for (const auto& f : cox_fixtures()) {
        INFO(f.name);
        CHECK(kaplan_meier(f.a).median_midpoint == f.midpoint_a);
        CHECK(kaplan_meier(f.b).median_midpoint == f.midpoint_b);
    }
}

namespace {

std::vector<std::string> split_csv_line(const std::string& line) {
    std::vector<std::string> fields;
    std::istringstream in(line);
    for (std::string field; std::getline(in, field, ',');) fields.push_back(field);
    if (!line.empty() && line.back() == ',') fields.emplace_back();
    return fields;
}

// the script's names of the statuses
CoxStatus oracle_status(const std::string& name) {
    if (name == "estimated") return CoxStatus::estimated;
    if (name == "tends_to_zero") return CoxStatus::tends_to_zero;
    if (name == "tends_to_infinity") return CoxStatus::tends_to_infinity;
    REQUIRE(name == "no_events");
    return CoxStatus::no_events;
}

// one treatment's times of one event in an events CSV (`stats --events-csv`)
Survival read_real_sample(const std::string& file, const std::string& treatment, const std::string& event) {
    std::ifstream in(file);
    REQUIRE(in);
    std::string line;
    std::getline(in, line);
    REQUIRE(line == "treatment,seed,event,generation,observed");
    Survival s;
    while (std::getline(in, line)) {
        const auto f = split_csv_line(line);
        REQUIRE(f.size() == 5);
        if (f[0] != treatment || f[2] != event) continue;
        s.time.push_back(std::stod(f[3]));
        s.observed.push_back(std::stoi(f[4]));
    }
    REQUIRE(s.time.size() == 20);
    return s;
}

}  // namespace

TEST_CASE("E1's and E2's hazard ratios and RMSTs equal statsmodels' on their committed events CSVs",
          "[stats][cox][results]") {
    // every event and pair of docs/results/e1_events.csv and e2_events.csv, both ties methods, as
    // tests/stats/hazard_oracle.py wrote them from PHReg and numpy
    const std::string source = STEPSTONE_SOURCE_DIR;
    std::ifstream in(source + "/tests/stats/hazard_results_expected.csv");
    REQUIRE(in);
    std::string line;
    std::getline(in, line);
    REQUIRE(line ==
            "file,event,treatment_a,treatment_b,ties,status,log_hr,se,hr,ci_low,ci_high,p_wald,rmst_a,rmst_b,"
            "horizon");
    std::size_t rows = 0, estimated = 0;
    while (std::getline(in, line)) {
        const auto f = split_csv_line(line);
        REQUIRE(f.size() == 15);
        INFO(line);
        const std::string file = source + "/docs/results/" + f[0];
        const Survival a = read_real_sample(file, f[2], f[1]), b = read_real_sample(file, f[3], f[1]);
        const Ties ties = f[4] == "efron" ? Ties::efron : Ties::breslow;
        const CoxResult r = cox_hazard_ratio(a, b, ties);
        CHECK(r.status == oracle_status(f[5]));
        if (f[5] == "estimated") {
            std::vector<double> expected;
            for (std::size_t k = 6; k < 12; ++k) expected.push_back(std::stod(f[k]));
            check_estimate(r, expected);
            ++estimated;
        }
        const double horizon = std::stod(f[14]);
        CHECK(restricted_mean(kaplan_meier(a), horizon) ==
              Approx(std::stod(f[12])).epsilon(1e-12).margin(1e-12));
        CHECK(restricted_mean(kaplan_meier(b), horizon) ==
              Approx(std::stod(f[13])).epsilon(1e-12).margin(1e-12));
        ++rows;
    }
    // 2 files x 4 events x 3 pairs x 2 ties methods
    CHECK(rows == 48);
    CHECK(estimated == 48);
}
