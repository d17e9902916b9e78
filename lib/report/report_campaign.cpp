// The campaign report: treatments compared (the paper's Fig. 6 and 7 and its
// appendix), the campaign's knowledge base (Fig. 3), the best source and
// target policies coloured by saliency (Fig. 4, 5 and 8), runs and provenance.

#include <algorithm>
#include <map>
#include <optional>

#include "core/error.hpp"
#include "core/output_file.hpp"
#include "core/text.hpp"
#include "core/version.hpp"
#include "db/database.hpp"
#include "report/chart.hpp"
#include "report/event_figures.hpp"
#include "report/figures.hpp"
#include "report/sections.hpp"
#include "runs/campaign_stats.hpp"
#include "runs/campaign_store.hpp"
#include "runs/run_store.hpp"

namespace stepstone::report {

namespace fs = std::filesystem;

namespace {

// the statistics at the asked generation, or at the last one every target
// run has reached when some are unfinished (said in `notes`)
std::optional<runs::CampaignStats> load_stats(const ReportOptions& options,
                                              const std::vector<runs::CampaignRun>& runs,
                                              std::vector<std::string>& notes) {
    try {
        return runs::campaign_stats(options.input, options.generation, options.threshold);
    } catch (const DataError& e) {
        if (options.generation) throw;
        int reached = -1;
        bool any = false;
        for (const auto& r : runs) {
            if (r.run.step != runs::CampaignStep::target) continue;
            reached = any ? std::min(reached, r.generations_done) : r.generations_done;
            any = true;
        }
        if (!any) {
            notes.push_back("the campaign has no target runs: no treatment comparison");
            return std::nullopt;
        }
        if (reached < 0) {
            // some target runs have not started: compare those that have finished, if any
            try {
                auto finished = runs::campaign_stats(options.input, std::nullopt, options.threshold, true);
                notes.push_back(concat(finished.skipped.size(), " target runs have not finished: the ",
                                       finished.runs.size(), " finished ones are compared at generation ",
                                       finished.generation));
                return finished;
            } catch (const DataError&) {
                notes.push_back(concat("treatments not compared: ", e.what()));
                return std::nullopt;
            }
        }
        notes.push_back(concat("some target runs are unfinished: treatments compared at generation ", reached,
                               ", the last one every target run has reached"));
        return runs::campaign_stats(options.input, reached, options.threshold);
    }
}

std::string p_value(double p) {
    char text[32];
    std::snprintf(text, sizeof text, p < 0.001 ? "%.2e" : "%.4f", p);
    return text;
}

void add_events(Page& page, const runs::CampaignStats& stats, const std::vector<runs::CampaignRun>& runs,
                const fs::path& dir);

// load(connection, run_id) of every target run file present, per treatment in the given order
template <class Load>
auto per_treatment(const std::vector<runs::CampaignRun>& runs, const fs::path& dir,
                   std::span<const runs::Treatment> treatments, Load load) {
    using Row = decltype(load(std::declval<db::Connection&>(), std::int64_t{}));
    std::vector<std::vector<Row>> series;
    for (const auto t : treatments) {
        series.emplace_back();
        for (const auto& r : runs) {
            if (r.run.step != runs::CampaignStep::target || r.run.treatment != t ||
                !fs::exists(dir / r.run.file))
                continue;
            auto connection = db::open_database(dir / r.run.file, db::OpenMode::read_only);
            series.back().push_back(load(connection, runs::load_run(connection).id));
        }
    }
    return series;
}

// `largest`: the largest average reward of each of the campaign's KBs ("kb", "kb-rand")
void add_statistics(Page& page, const runs::CampaignStats& stats, const std::vector<runs::CampaignRun>& runs,
                    const fs::path& dir, const std::map<std::string, double>& largest) {
    page.heading("Treatments compared");
    page.paragraph(concat("Target runs at generation ", stats.generation, "; a run succeeds when its best-of-run task "
                          "reward reaches ", fixed(stats.threshold, 3), ". The paper reports, at generation 3000 "
                          "with 20 runs each: sum 35 %, mo 30 %, every control 0 %."));
    std::vector<std::vector<std::string>> rows;
    for (const auto& t : stats.treatments) {
        const auto& s = t.summary;
        rows.push_back({std::string(runs::to_string(t.treatment)), std::to_string(s.n),
                        concat(t.successes, " (",
                               fixed(100.0 * static_cast<double>(t.successes) /
                                         static_cast<double>(std::max<std::size_t>(s.n, 1)),
                                     0),
                               " %)"),
                        fixed(s.min, 4), fixed(s.q1, 4), fixed(s.median, 4), fixed(s.q3, 4), fixed(s.max, 4),
                        t.mean_r_max ? fixed(*t.mean_r_max, 3) : std::string("-"), std::to_string(t.policies),
                        std::to_string(t.ball_policies)});
    }
    page.table(
        {"treatment", "runs", "successes", "min", "q1", "median", "q3", "max",
         concat("r_max, gen. ", stats.signal_from, "-", stats.generation), "policies", "with a ball"},
        rows,
        "Best-of-run task reward per treatment (quartiles: R type 7); the shaping signal (mean r_max of the "
        "policies of the last generations); the policies evaluated, and those that collected a ball");
    page.figure("successes", kFigureWidth, kFigureHeight,
                "Successful runs per treatment along generations (the paper's Fig. 6).",
                [&](Canvas& c) { draw_successes(c, stats); });
    page.figure("best-of-run", kFigureWidth, kFigureHeight,
                concat("Best-of-run task reward of every target run at generation ", stats.generation,
                       ", jittered sideways; black bars are medians (the paper's Fig. 7)."),
                [&](Canvas& c) { draw_best_of_run(c, stats); });
    page.figure("treatment-rewards", kFigureWidth, kFigureHeight,
                "Best-so-far task reward along generations: per treatment the median over seeds (line) and the "
                "quartiles (band).",
                [&](Canvas& c) { draw_treatment_rewards(c, stats); });

    std::vector<std::vector<std::string>> tests;
    for (const auto& t : stats.tests) {
        tests.push_back({concat(runs::to_string(t.a), " vs ", runs::to_string(t.b)),
                         concat(t.n_a, " / ", t.n_b), fixed(t.test.u, 1), p_value(t.p),
                         std::string(runs::to_string(t.method)), p_value(t.test.p), p_value(t.p_holm),
                         fixed(t.a12, 3)});
    }
    page.table(
        {"pair", "runs", "U (first)", "p (two-sided)", "p from", "p (SciPy auto)", "p (Holm)",
         "A12 (first over second)"},
        tests,
        concat("Mann-Whitney U on the best-of-run rewards, Holm-adjusted over every pair, and Vargha-Delaney "
               "A12. Below ",
               runs::kPermutationBelowRuns,
               " runs an arm, or when a quarter of the values tie, "
               "p is the exact permutation p (every relabelling, ties kept); SciPy's method=\"auto\" p is "
               "shown beside it. The paper: sum vs none p = 0.011, mo vs none p = 0.0054."));
    add_events(page, stats, runs, dir);

    // the shaping signal, from every target run's individual table
    std::vector<runs::Treatment> treatments;
    for (const auto& t : stats.treatments) treatments.push_back(t.treatment);
    const auto series = per_treatment(runs, dir, treatments, runs::load_generations);
    page.figure("treatment-medians", kFigureWidth, kFigureHeight,
                "The median task reward of each generation's survivors: per treatment the median over seeds (line) "
                "and the quartiles (band).",
                [&](Canvas& c) { draw_treatment_medians(c, treatments, series); });
    const bool shaped = std::any_of(series.begin(), series.end(), [](const auto& t) {
        return std::any_of(t.begin(), t.end(), [](const auto& run) {
            return std::any_of(run.begin(), run.end(),
                               [](const auto& g) { return g.mean_r_max.has_value(); });
        });
    });
    if (shaped) {
        // as sum adds it: r_max over the largest average A of the KB the treatment reads, so that a real KB
        // (A ~ 0.15) and its randomized twin (A ~ 1) share one axis
        auto normalised = series;
        std::string divisors;
        for (std::size_t t = 0; t < treatments.size() && t < normalised.size(); ++t) {
            if (!runs::needs_kb(treatments[t])) continue;
            const auto kb = largest.find(runs::needs_randomized_kb(treatments[t]) ? "kb-rand" : "kb");
            const double a = kb == largest.end() ? 0.0 : kb->second;
            for (auto& run : normalised[t]) {
                for (auto& g : run) {
                    if (g.mean_r_max)
                        g.mean_r_max = a > 0.0 ? std::optional(*g.mean_r_max / a) : std::nullopt;
                }
            }
        }
        for (const auto& [name, a] : largest)
            divisors += concat(divisors.empty() ? "" : ", ", name, " ", fixed(a, 3));
        page.figure(
            "treatment-shaping", kFigureWidth, kFigureHeight,
            concat("The shaping signal as sum adds it: mean r_max / A of the policies evaluated in each "
                   "generation, median over seeds with the quartile band, where A is the largest average "
                   "reward of the KB the treatment reads (",
                   divisors,
                   "). The -rand treatments read the randomized KB, whose averages are U[0, 1) draws. "
                   "A treatment drawn exactly over another is named so in the legend."),
            [&](Canvas& c) { draw_treatment_shaping(c, treatments, normalised); });
    }
}

// the time to each milestone: Kaplan-Meier figure, log-rank table, shares of policies
void add_events(Page& page, const runs::CampaignStats& stats, const std::vector<runs::CampaignRun>& runs,
                const fs::path& dir) {
    page.heading("Milestones: when runs first reach each step of the task");
    if (!stats.events) {
        page.paragraph(
            concat("<span class=\"note\">Note: ", stats.unrecorded.size(), " of ", stats.runs.size(),
                   " target runs were written before milestones were recorded (schema 0005), so there "
                   "are no time-to-event statistics.</span>"));
        return;
    }
    const auto& events = *stats.events;
    page.paragraph(
        concat("For every run and milestone, the first generation in which any evaluated policy reached "
               "it; runs that never did are right-censored at generation ",
               stats.generation, " (docs/statistics.md)."));
    page.figure(
        "kaplan-meier", kPanelFigureWidth, kPanelFigureHeight,
        "Kaplan-Meier curves of the time to each milestone: the share of runs that have not reached it yet, "
        "per treatment; a tick marks censored runs, the table under each axis gives the runs still at risk.",
        [&](Canvas& c) { draw_kaplan_meier(c, events); });
    std::vector<std::vector<std::string>> rows;
    for (const auto& t : events.tests) {
        rows.push_back({std::string(runs::to_string(t.milestone)),
                        concat(runs::to_string(t.a), " vs ", runs::to_string(t.b)),
                        concat(t.n_a, " / ", t.n_b), concat(t.test.events_a, " / ", t.test.events_b),
                        fixed(t.test.chi2, 3), p_value(t.test.p), p_value(t.p_holm)});
    }
    page.table(
        {"milestone", "pair", "runs", "reached", "chi2 (1 df)", "p", "p (Holm)"}, rows,
        "Log-rank tests of the time to each milestone, Holm-adjusted over the pairs of each milestone.");
    std::vector<std::vector<std::string>> medians;
    for (const auto& s : events.summaries) {
        medians.push_back({std::string(runs::to_string(s.milestone)),
                           std::string(runs::to_string(s.treatment)), concat(s.reached, " of ", s.runs),
                           s.curve.median ? concat(*s.curve.median) : std::string("not reached")});
    }
    page.table({"milestone", "treatment", "runs that reached it", "Kaplan-Meier median generation"}, medians);

    const auto series = per_treatment(runs, dir, events.treatments, runs::load_milestone_counts);
    page.figure(
        "milestone-shares", kPanelFigureWidth, kPanelFigureHeight,
        "The share of each generation's policies that reached each milestone: per treatment the median over "
        "seeds (line) and the quartiles (band). Every evaluated policy counts, stored or not.",
        [&](Canvas& c) { draw_milestone_shares(c, events.treatments, series); });
}

// the finished run of `step` with the highest best reward (first on ties)
const runs::CampaignRun* best_run(const std::vector<runs::CampaignRun>& runs, runs::CampaignStep step) {
    const runs::CampaignRun* best = nullptr;
    for (const auto& r : runs) {
        if (r.run.step != step || !r.best_reward || r.generations_done < 0) continue;
        if (best == nullptr || *r.best_reward > *best->best_reward) best = &r;
    }
    return best;
}

}  // namespace

void campaign_report(const ReportOptions& options, const fs::path& dir, ReportSummary& summary) {
    const fs::path& campaign_dir = options.input;
    auto connection = db::open_database(campaign_dir / "campaign.db", db::OpenMode::read_only);
    const auto index = runs::load_campaign(connection);
    const auto& runs = index.runs;
    const auto kbs = runs::load_campaign_kbs(connection);
    Progress progress("report", 4, options.progress);
    Page page(dir, concat("stepstone report: campaign ", campaign_dir.lexically_normal().string()));

    std::size_t finished = 0;
    for (const auto& r : runs) finished += r.status == runs::RunStatus::finished;
    page.paragraph(concat("Campaign directory <code>", xml_escape(campaign_dir.string()), "</code>: ", runs.size(),
                          " runs, ", finished, " finished."));

    // the knowledge bases, for the shaping figure and the policies they colour
    std::map<std::string, db::StoredKb> loaded;
    std::map<std::string, double> largest;
    for (const auto& k : kbs) {
        if (!fs::exists(campaign_dir / k.file)) continue;
        auto kb_connection = db::open_database(campaign_dir / k.file, db::OpenMode::read_only);
        const auto& stored = loaded.emplace(k.name, db::load_kb(kb_connection)).first->second;
        largest.emplace(k.name, stored.kb.max_average());
    }

    const auto stats = load_stats(options, runs, summary.notes);
    for (const auto& note : summary.notes)
        page.paragraph(concat("<span class=\"note\">Note: ", xml_escape(note), ".</span>"));
    if (stats) add_statistics(page, *stats, runs, campaign_dir, largest);
    progress.update(1);

    const auto kb_it = loaded.find("kb");
    const db::StoredKb* kb = kb_it == loaded.end() ? nullptr : &kb_it->second;
    if (kb != nullptr) {
        page.heading("The knowledge base");
        const auto row = std::find_if(kbs.begin(), kbs.end(), [](const auto& k) { return k.name == "kb"; });
        add_kb_section(page, "", *kb, row->made_from);
    }
    progress.update(2);
    if (const auto* source = best_run(runs, runs::CampaignStep::source)) {
        page.heading("The best source policy");
        const auto trace = trace_policy(campaign_dir / source->run.file, "best", 0, kb ? &kb->kb : nullptr,
                                        kb ? kb->name : "");
        add_trajectory(page, "source-best", trace, concat("The best policy of ", source->run.file));
    }
    progress.update(3);
    if (const auto* target = best_run(runs, runs::CampaignStep::target)) {
        // a best reward of 0 is no best policy: say so, and show what the runs reached
        const bool scored = *target->best_reward > 0;
        page.heading(scored ? "The best target policy" : "No target policy scored");
        if (!scored) {
            page.paragraph(
                concat("No target run has a policy that collected a ball (every best reward is 0). "
                       "Below: the first stored policy of ",
                       xml_escape(target->run.file),
                       ", to show where such policies drive; the milestones above say how far the "
                       "runs got."));
        }
        // coloured by the KB the run was shaped with
        const bool randomized = runs::needs_randomized_kb(target->run.treatment);
        const auto it = loaded.find(randomized ? "kb-rand" : "kb");
        const db::StoredKb* used = it == loaded.end() ? nullptr : &it->second;
        const auto trace = trace_policy(campaign_dir / target->run.file, "best", 0,
                                        used ? &used->kb : nullptr, used ? used->name : "");
        add_trajectory(
            page, "target-best", trace,
            concat(scored ? "The best policy of " : "A policy of ", target->run.file, " (treatment ",
                   runs::to_string(target->run.treatment), scored ? ")" : ", reward 0)"));
    }
    progress.update(4);

    page.heading("Runs");
    std::vector<std::vector<std::string>> rows;
    for (const auto& r : runs) {
        rows.push_back({r.run.file, std::string(runs::to_string(r.run.step)),
                        std::string(runs::to_string(r.run.treatment)), std::to_string(r.run.seed),
                        concat(r.generations_done, " / ", r.run.generations),
                        std::string(runs::to_string(r.status)),
                        r.best_reward ? fixed(*r.best_reward, 4) : "-", format_duration(r.wall_time),
                        r.digest.empty() ? (r.error.empty() ? "-" : r.error) : r.digest.substr(0, 16)});
    }
    page.table({"file", "step", "treatment", "seed", "generations", "status", "best reward", "time",
                "digest (first 16 hex) or error"},
               rows);
    if (!kbs.empty()) {
        std::vector<std::vector<std::string>> kb_rows;
        for (const auto& k : kbs) kb_rows.push_back({k.name, k.file, k.made_from, std::to_string(k.segments), k.digest});
        page.table({"KB", "file", "made from", "segments", "content digest"}, kb_rows, "Knowledge bases");
    }
    page.heading("Provenance");
    page.paragraph(
        concat("Report written by stepstone ", full_version(),
               ". Every run file's digest "
               "(<code>stepstone db digest</code>) is in the runs table; the same seeds and configs give "
               "the same digests on any machine and thread count."));
    page.heading("Campaign config", 3);
    page.preformatted(index.config.dump(2));
    progress.finish();

    write_index(page, dir, summary);
}

}  // namespace stepstone::report
