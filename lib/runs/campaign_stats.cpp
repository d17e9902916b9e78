#include "runs/campaign_stats.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/error.hpp"
#include "core/text.hpp"
#include "db/database.hpp"
#include "db/inspect.hpp"
#include "runs/campaign_store.hpp"
#include "runs/run_store.hpp"
#include "stats/survival.hpp"

namespace stepstone::runs {

namespace fs = std::filesystem;

namespace {

// The run's best-so-far rewards; when it has reached `generation`, also its
// policies, those with a ball and its mean r_max from `signal_from` on.
RunCurve read_curve(const fs::path& dir, const PlannedRun& run, int generation, int signal_from) {
    const fs::path path = dir / run.file;
    if (!fs::exists(path)) {
        throw DataError(
            concat(path.string(), ": missing (campaign.db lists it; resuming the campaign runs it)"));
    }
    auto connection = db::open_database(path, db::OpenMode::read_only);
    const RunRecord record = load_run(connection);
    const bool milestones = db::has_milestones(connection);
    if (static_cast<std::uint64_t>(record.seed) != run.seed || record.treatment != to_string(run.treatment)) {
        throw DataError(concat(path.string(), ": holds a run of seed ", record.seed, " treatment ",
                               record.treatment, ", campaign.db expects seed ", run.seed, " treatment ",
                               to_string(run.treatment)));
    }
    RunCurve curve;
    curve.treatment = run.treatment;
    curve.seed = run.seed;
    curve.file = run.file;
    auto rows = connection.prepare(db::sql("run/select_best_rewards.sql"));
    rows.bind(":run_id", record.id);
    double best = 0;
    while (rows.step()) {
        const auto g = rows.column_int(0);
        const double reward = rows.column_double(1);
        if (g != static_cast<std::int64_t>(curve.best.size()) || !std::isfinite(reward)) {
            throw DataError(concat(path.string(), ": the generation table is damaged near generation ", g));
        }
        best = curve.best.empty() ? reward : std::max(best, reward);
        curve.best.push_back(best);
    }
    if (static_cast<int>(curve.best.size()) <= generation) return curve;
    auto signal = connection.prepare(db::sql("run/select_signal.sql"));
    signal.bind(":run_id", record.id);
    signal.bind(":from", static_cast<std::int64_t>(signal_from));
    signal.bind(":to", static_cast<std::int64_t>(generation));
    if (signal.step()) {
        curve.policies = signal.column_int(0);
        curve.ball_policies = signal.column_int(1);
        if (!signal.is_null(2)) curve.mean_r_max = signal.column_double(2);
    }
    if (!milestones) return curve;
    auto first = connection.prepare(db::sql("run/select_first_events.sql"));
    first.bind(":run_id", record.id);
    first.bind(":to", static_cast<std::int64_t>(generation));
    if (first.step() && first.column_int(4) == first.column_int(5)) {
        FirstEvents events;
        for (std::size_t m = 0; m < kMilestones; ++m) {
            const int column = static_cast<int>(m);
            if (!first.is_null(column)) events[m] = static_cast<int>(first.column_int(column));
        }
        curve.first_events = events;
    }
    return curve;
}

std::string short_number(double value) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.4g", value);
    return buffer;
}

// every run's row at the chosen generation
std::vector<RunRow> run_rows(const CampaignStats& stats) {
    const auto g = static_cast<std::size_t>(stats.generation);
    std::vector<RunRow> rows;
    for (const auto& run : stats.runs) {
        rows.push_back({run.treatment, run.seed, stats.generation, run.best[g],
                        run.best[g] >= stats.threshold, run.policies, run.ball_policies, run.mean_r_max});
    }
    return rows;
}

}  // namespace

std::vector<PairTest> pair_tests(std::span<const TreatmentResult> treatments) {
    std::vector<PairTest> tests;
    std::vector<double> p;
    for (std::size_t a = 0; a < treatments.size(); ++a) {
        for (std::size_t b = a + 1; b < treatments.size(); ++b) {
            const auto& ta = treatments[a];
            const auto& tb = treatments[b];
            PairTest test;
            test.a = ta.treatment;
            test.b = tb.treatment;
            test.n_a = ta.best.size();
            test.n_b = tb.best.size();
            test.test = stats::mann_whitney_u(ta.best, tb.best);
            test.a12 = stats::vargha_delaney_a12(ta.best, tb.best);
            test.tied_share = stats::tied_share(ta.best, tb.best);
            test.p = test.test.p;
            test.method = test.test.method == stats::Method::exact ? PairMethod::exact : PairMethod::normal;
            if (std::min(test.n_a, test.n_b) < kPermutationBelowRuns ||
                test.tied_share >= kPermutationTiedShare) {
                const stats::PermutationP permutation = stats::permutation_p(ta.best, tb.best);
                test.p = permutation.p;
                test.method = permutation.exact ? PairMethod::permutation : PairMethod::monte_carlo;
                test.p_standard_error = permutation.standard_error;
            }
            tests.push_back(test);
            p.push_back(test.p);
        }
    }
    const auto adjusted = stats::holm(p);
    for (std::size_t k = 0; k < tests.size(); ++k) tests[k].p_holm = adjusted[k];
    return tests;
}

CampaignStats campaign_stats(const fs::path& dir, std::optional<int> generation, double threshold,
                             bool available_only, int signal_window) {
    if (!(threshold >= 0.0 && threshold <= 1.0)) {
        throw ConfigError(concat(option_name("threshold"), " must be within [0, 1], got ", threshold));
    }
    if (generation && *generation < 0)
        throw ConfigError(concat(option_name("generation"), " must be >= 0, got ", *generation));
    if (signal_window < 1)
        throw ConfigError(concat(option_name("signal_window"), " must be >= 1, got ", signal_window));
    const CampaignIndex index = load_campaign(dir);

    CampaignStats stats;
    stats.dir = dir.string();
    stats.threshold = threshold;
    for (const auto& indexed : index.runs) {
        const PlannedRun& run = indexed.run;
        if (run.step != CampaignStep::target) continue;
        if (!generation) generation = run.generations;
        stats.signal_from = std::max(0, *generation - signal_window + 1);
        if (*generation > run.generations) {
            // resuming cannot help: the campaign asks for fewer generations
            throw ConfigError(
                concat(option_name("generation"), " ", *generation, " is beyond the ", run.generations,
                       " generations the campaign's target runs are asked for (", (dir / run.file).string(),
                       "); use ", option_name("generation"), " ", run.generations, " or less"));
        }
        if (available_only && !fs::exists(dir / run.file)) {
            stats.skipped.push_back(run.file);
            continue;
        }
        stats.runs.push_back(read_curve(dir, run, *generation, stats.signal_from));
        const auto& curve = stats.runs.back();
        if (static_cast<int>(curve.best.size()) <= *generation && available_only) {
            stats.skipped.push_back(run.file);
            stats.runs.pop_back();
            continue;
        }
        if (static_cast<int>(curve.best.size()) <= *generation) {
            const int reached = static_cast<int>(curve.best.size()) - 1;
            throw DataError(concat((dir / run.file).string(), ": has reached generation ", reached, " of ",
                                   *generation, "; finish it (resume the campaign) or use ",
                                   option_name("generation"), " ", std::max(reached, 0)));
        }
        auto it = std::find_if(stats.treatments.begin(), stats.treatments.end(),
                               [&](const TreatmentResult& t) { return t.treatment == run.treatment; });
        if (it == stats.treatments.end()) {
            TreatmentResult fresh;
            fresh.treatment = run.treatment;
            stats.treatments.push_back(fresh);
            it = stats.treatments.end() - 1;
        }
    }
    if (stats.runs.empty() && !stats.skipped.empty()) {
        throw DataError(concat(dir.string(), ": no target run has reached generation ", *generation, " yet"));
    }
    if (stats.runs.empty()) throw DataError(concat(dir.string(), ": the campaign has no target runs"));
    stats.generation = *generation;
    const auto g = static_cast<std::size_t>(stats.generation);

    const std::vector<RunRow> rows = run_rows(stats);
    for (auto& t : stats.treatments) t = treatment_result(t.treatment, rows, threshold);
    stats.successes.assign(g + 1, std::vector<std::size_t>(stats.treatments.size(), 0));
    for (std::size_t k = 0; k <= g; ++k) {
        for (std::size_t t = 0; t < stats.treatments.size(); ++t) {
            for (const auto& run : stats.runs) {
                if (run.treatment == stats.treatments[t].treatment && run.best[k] >= threshold) {
                    ++stats.successes[k][t];
                }
            }
        }
    }
    stats.tests = pair_tests(stats.treatments);

    std::vector<RunEvents> run_events;
    for (const auto& run : stats.runs) {
        if (!run.first_events) {
            stats.unrecorded.push_back(run.file);
            continue;
        }
        run_events.push_back({run.treatment, run.seed, *run.first_events});
    }
    if (stats.unrecorded.empty()) {
        std::vector<Treatment> order;
        for (const auto& t : stats.treatments) order.push_back(t.treatment);
        stats.events = campaign_events(run_events, order, stats.generation);
    }
    return stats;
}

std::string_view to_string(PairMethod method) {
    switch (method) {
        case PairMethod::exact:
            return "exact";
        case PairMethod::normal:
            return "normal";
        case PairMethod::permutation:
            return "permutation";
        case PairMethod::monte_carlo:
            return "monte-carlo";
    }
    return "?";
}

void require_events(const CampaignStats& stats) {
    if (stats.events) return;
    throw DataError(concat(stats.dir, ": ", stats.unrecorded.size(), " of ", stats.runs.size(),
                           " target runs do not record milestones (written before schema 0005), e.g. ",
                           stats.unrecorded.front(),
                           "; time-to-event statistics need runs made by this version"));
}

void write_treatment_tables(std::ostream& out, std::span<const TreatmentResult> treatments,
                            std::string_view signal, int generation) {
    char line[256];
    std::snprintf(line, sizeof line, "%-10s %5s %8s %8s %8s %8s %8s\n", "treatment", "runs", "success", "q1",
                  "median", "q3", "max");
    out << line;
    for (const auto& t : treatments) {
        std::snprintf(line, sizeof line, "%-10s %5zu %8zu %8.4g %8.4g %8.4g %8.4g\n",
                      std::string(to_string(t.treatment)).c_str(), t.best.size(), t.successes, t.summary.q1,
                      t.summary.median, t.summary.q3, t.summary.max);
        out << line;
    }

    out << "\nshaping signal (r_max: " << signal << "), and policies that collected a ball (generations 0-"
        << generation << ")\n";
    std::snprintf(line, sizeof line, "%-10s %8s %12s %10s\n", "treatment", "r_max", "policies", "with_ball");
    out << line;
    for (const auto& t : treatments) {
        const std::string r_max = t.mean_r_max ? short_number(*t.mean_r_max) : "-";
        std::snprintf(line, sizeof line, "%-10s %8s %12lld %10lld\n",
                      std::string(to_string(t.treatment)).c_str(), r_max.c_str(),
                      static_cast<long long>(t.policies), static_cast<long long>(t.ball_policies));
        out << line;
    }
}

void write_pair_tests(std::ostream& out, std::span<const PairTest> tests, int generation) {
    char line[256];
    if (tests.empty()) return;
    out << "\nMann-Whitney U, two-sided, at generation " << generation << " (p_holm: Holm-adjusted over the "
        << tests.size() << " pairs; A12: P(a > b) + P(a = b) / 2;"
        << " method: how p was obtained, permutation below " << kPermutationBelowRuns
        << " runs an arm or with ties, docs/statistics.md)\n";
    std::snprintf(line, sizeof line, "%-10s %-10s %4s %4s %8s %10s %10s %6s  %s\n", "a", "b", "n_a", "n_b",
                  "U", "p", "p_holm", "A12", "method");
    out << line;
    for (const auto& t : tests) {
        std::snprintf(line, sizeof line, "%-10s %-10s %4zu %4zu %8s %10.4g %10.4g %6.3f  %s\n",
                      std::string(to_string(t.a)).c_str(), std::string(to_string(t.b)).c_str(), t.n_a, t.n_b,
                      short_number(t.test.u).c_str(), t.p, t.p_holm, t.a12,
                      std::string(to_string(t.method)).c_str());
        out << line;
    }
}

void write_text(std::ostream& out, const CampaignStats& stats, Milestone event) {
    char line[256];
    out << "campaign " << stats.dir << ": " << stats.runs.size() << " target runs at generation "
        << stats.generation << "; success = best-of-run reward >= " << stats.threshold << "\n";
    if (!stats.skipped.empty()) {
        out << stats.skipped.size() << " target runs not yet at generation " << stats.generation
            << " left out (only the available runs were asked for):";
        for (const auto& file : stats.skipped) out << " " << file;
        out << "\n";
    }
    out << "\n";
    write_treatment_tables(
        out, stats.treatments,
        concat("mean over runs of the mean r_max of generations ", stats.signal_from, "-", stats.generation,
               "; raw averages, not divided by the KB's largest as the report's figure is"),
        stats.generation);
    out << "\nsuccessful runs by generation\n";
    std::snprintf(line, sizeof line, "%-10s", "generation");
    out << line;
    for (const auto& t : stats.treatments) {
        std::snprintf(line, sizeof line, " %9s", std::string(to_string(t.treatment)).c_str());
        out << line;
    }
    out << "\n";
    // about ten rows, evenly spaced, always ending at the chosen generation
    const std::size_t last = stats.successes.size() - 1;
    const std::size_t step = std::max<std::size_t>(1, (last + 9) / 10);
    for (std::size_t g = 0;; g = std::min(g + step, last)) {
        std::snprintf(line, sizeof line, "%-10zu", g);
        out << line;
        for (std::size_t count : stats.successes[g]) {
            std::snprintf(line, sizeof line, " %9zu", count);
            out << line;
        }
        out << "\n";
        if (g == last) break;
    }

    if (!stats.events) {
        out << "\nmilestones: not recorded by " << stats.unrecorded.size() << " of " << stats.runs.size()
            << " target runs (written before schema 0005); no time-to-event statistics\n";
    }
    write_pair_tests(out, stats.tests, stats.generation);
    if (stats.events) write_events_text(out, *stats.events, event);
}

void write_events_csv(std::ostream& out, const CampaignStats& stats) {
    require_events(stats);
    std::vector<RunEvents> runs;
    for (const auto& run : stats.runs) runs.push_back({run.treatment, run.seed, *run.first_events});
    write_events_csv(out, runs, stats.generation);
}

void write_logrank_csv(std::ostream& out, const CampaignStats& stats) {
    require_events(stats);
    write_logrank_csv(out, *stats.events);
}

void write_hazard_csv(std::ostream& out, const CampaignStats& stats) {
    require_events(stats);
    write_hazard_csv(out, *stats.events);
}

void write_success_csv(std::ostream& out, const CampaignStats& stats) {
    out << "generation";
    for (const auto& t : stats.treatments) out << "," << to_string(t.treatment);
    out << "\n";
    for (std::size_t g = 0; g < stats.successes.size(); ++g) {
        out << g;
        for (std::size_t count : stats.successes[g]) out << "," << count;
        out << "\n";
    }
}

void write_run_rows(std::ostream& out, std::span<const RunRow> rows) {
    out << "treatment,seed,generation,best_reward,success,policies,ball_policies,mean_r_max\n";
    for (const auto& row : rows) {
        out << to_string(row.treatment) << "," << row.seed << "," << row.generation << ","
            << exact(row.best_reward) << "," << (row.success ? 1 : 0) << "," << row.policies << ","
            << row.ball_policies << "," << (row.mean_r_max ? exact(*row.mean_r_max) : "") << "\n";
    }
}

void write_runs_csv(std::ostream& out, const CampaignStats& stats) { write_run_rows(out, run_rows(stats)); }

TreatmentResult treatment_result(Treatment t, std::span<const RunRow> runs, double threshold) {
    TreatmentResult result;
    result.treatment = t;
    double r_max_sum = 0;
    std::size_t with_r_max = 0;
    for (const auto& run : runs) {
        if (run.treatment != t) continue;
        result.best.push_back(run.best_reward);
        result.policies += run.policies;
        result.ball_policies += run.ball_policies;
        if (run.mean_r_max) {
            r_max_sum += *run.mean_r_max;
            ++with_r_max;
        }
    }
    if (with_r_max > 0) result.mean_r_max = r_max_sum / static_cast<double>(with_r_max);
    result.summary = stats::summarize(result.best);
    result.successes = stats::count_at_least(result.best, threshold);
    return result;
}

void write_pair_tests_csv(std::ostream& out, std::span<const PairTest> tests) {
    out << "treatment_a,treatment_b,n_a,n_b,u,p,p_holm,a12,method,p_auto,p_se\n";
    for (const auto& t : tests) {
        out << to_string(t.a) << "," << to_string(t.b) << "," << t.n_a << "," << t.n_b << ","
            << exact(t.test.u) << "," << exact(t.p) << "," << exact(t.p_holm) << "," << exact(t.a12) << ","
            << to_string(t.method) << "," << exact(t.test.p) << ","
            << (t.method == PairMethod::monte_carlo ? exact(t.p_standard_error) : "") << "\n";
    }
}

void write_tests_csv(std::ostream& out, const CampaignStats& stats) {
    write_pair_tests_csv(out, stats.tests);
}

}  // namespace stepstone::runs
