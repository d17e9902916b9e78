#include "runs/campaign_events.hpp"

#include <algorithm>
#include <cstdio>
#include <utility>

#include "core/error.hpp"
#include "core/text.hpp"
#include "stats/mann_whitney.hpp"

namespace stepstone::runs {

namespace {

constexpr std::array<Milestone, kMilestones> kAll{Milestone::press, Milestone::pickup, Milestone::release,
                                                  Milestone::ball};

// a run's time for milestone m: its first generation when reached by `generation`, else
// censored at `generation` (observed false)
std::pair<int, bool> event_time(const RunEvents& run, Milestone m, int generation) {
    const auto& first = run.first[static_cast<std::size_t>(m)];
    const bool observed = first.has_value() && *first <= generation;
    return {observed ? *first : generation, observed};
}

// one treatment's event times for one milestone, censored at `generation`
stats::Survival survival_of(std::span<const RunEvents> runs, Treatment treatment, Milestone m,
                            int generation) {
    stats::Survival s;
    for (const auto& run : runs) {
        if (run.treatment != treatment) continue;
        const auto [time, observed] = event_time(run, m, generation);
        s.time.push_back(time);
        s.observed.push_back(observed ? 1 : 0);
    }
    return s;
}

std::string_view description(Milestone m) {
    switch (m) {
        case Milestone::press:
            return "pressed the switch";
        case Milestone::pickup:
            return "picked a ball up";
        case Milestone::release:
            return "released a ball within the basket radius";
        case Milestone::ball:
            return "collected a ball";
    }
    return "";
}

// "34", or "34 (midpoint 29.5)" where R's survfit convention differs, "not reached"
std::string median_text(const stats::KaplanMeier& curve) {
    std::string text = curve.median ? concat(*curve.median) : "not reached";
    if (curve.median_midpoint && curve.median_midpoint != curve.median)
        text += concat(" (midpoint ", *curve.median_midpoint, ")");
    return text;
}

// "0.851 [0.44, 1.65]", or why there is no estimate
std::string hazard_text(const EventTest& t) {
    if (!t.cox.estimate) return "not estimable: " + hazard_note(t);
    char text[96];
    std::snprintf(text, sizeof text, "%.3g [%.3g, %.3g]", t.cox.estimate->hr, t.cox.estimate->ci_low,
                  t.cox.estimate->ci_high);
    return text;
}

}  // namespace

std::string hazard_note(const EventTest& test) {
    const std::string a(to_string(test.a)), b(to_string(test.b));
    switch (test.cox.status) {
        case stats::CoxStatus::estimated:
            return "";
        case stats::CoxStatus::no_events:
            return "no events in either arm";
        case stats::CoxStatus::never_together:
            return "no event time with both arms at risk";
        case stats::CoxStatus::tends_to_zero:
            return test.cox.events_a == 0 ? concat("no events in ", a, " (HR -> 0)")
                                          : concat("no event of ", a, " while ", b, " at risk (HR -> 0)");
        case stats::CoxStatus::tends_to_infinity:
            return test.cox.events_b == 0 ? concat("no events in ", b, " (HR -> inf)")
                                          : concat("no event of ", b, " while ", a, " at risk (HR -> inf)");
    }
    return "";
}

std::span<const Milestone> all_milestones() { return kAll; }

std::string_view to_string(Milestone m) {
    switch (m) {
        case Milestone::press:
            return "press";
        case Milestone::pickup:
            return "pickup";
        case Milestone::release:
            return "release";
        case Milestone::ball:
            return "ball";
    }
    return "?";
}

Milestone parse_milestone(std::string_view name, std::string_view what) {
    for (Milestone m : kAll) {
        if (to_string(m) == name) return m;
    }
    throw ConfigError(concat(what, ": unknown milestone '", name, "' (one of press, pickup, release, ball)"));
}

CampaignEvents campaign_events(std::span<const RunEvents> runs, std::span<const Treatment> treatments,
                               int generation) {
    CampaignEvents events;
    events.generation = generation;
    events.treatments.assign(treatments.begin(), treatments.end());
    for (Milestone m : kAll) {
        std::vector<stats::Survival> samples;
        for (Treatment t : treatments) {
            samples.push_back(survival_of(runs, t, m, generation));
            EventSummary summary;
            summary.treatment = t;
            summary.milestone = m;
            summary.runs = samples.back().time.size();
            summary.curve = stats::kaplan_meier(samples.back());
            summary.reached = summary.curve.events;
            summary.rmst = stats::restricted_mean(summary.curve, generation);
            events.summaries.push_back(summary);
        }
        std::vector<double> p;
        const std::size_t first_test = events.tests.size();
        for (std::size_t a = 0; a < treatments.size(); ++a) {
            for (std::size_t b = a + 1; b < treatments.size(); ++b) {
                EventTest test;
                test.a = treatments[a];
                test.b = treatments[b];
                test.milestone = m;
                test.n_a = samples[a].time.size();
                test.n_b = samples[b].time.size();
                test.test = stats::log_rank(samples[a], samples[b]);
                test.cox = stats::cox_hazard_ratio(samples[a], samples[b], kHazardTies);
                const std::size_t summaries = events.summaries.size() - treatments.size();
                test.rmst_a = events.summaries[summaries + a].rmst;
                test.rmst_b = events.summaries[summaries + b].rmst;
                events.tests.push_back(test);
                p.push_back(test.test.p);
            }
        }
        const auto adjusted = stats::holm(p);
        for (std::size_t k = 0; k < adjusted.size(); ++k) events.tests[first_test + k].p_holm = adjusted[k];
    }
    return events;
}

void write_events_text(std::ostream& out, const CampaignEvents& events, Milestone milestone) {
    char line[256];
    out << "\ntime to first " << to_string(milestone) << ": the first generation in which a policy "
        << description(milestone) << " (runs without one censored at generation " << events.generation
        << ")\n";
    const std::string rmst_header = concat("RMST 0-", events.generation);
    std::snprintf(line, sizeof line, "%-10s %5s %8s %24s %12s\n", "treatment", "runs", "reached",
                  "median (KM)", rmst_header.c_str());
    out << line;
    for (const auto& s : events.summaries) {
        if (s.milestone != milestone) continue;
        std::snprintf(line, sizeof line, "%-10s %5zu %8zu %24s %12.4g\n",
                      std::string(to_string(s.treatment)).c_str(), s.runs, s.reached,
                      median_text(s.curve).c_str(), s.rmst);
        out << line;
    }
    const auto pairs = std::count_if(events.tests.begin(), events.tests.end(),
                                     [&](const EventTest& t) { return t.milestone == milestone; });
    if (pairs == 0) return;
    out << "\nlog-rank, time to first " << to_string(milestone)
        << " (p: chi-square with 1 df; p_holm: over the " << pairs << " pairs), RMST a-b (generations, up to "
        << events.generation << ") and the Cox hazard ratio of a to b (" << to_string(kHazardTies)
        << " ties, 95% Wald CI)\n";
    std::snprintf(line, sizeof line, "%-10s %-10s %4s %4s %8s %8s %8s %10s %10s %9s  %s\n", "a", "b", "n_a",
                  "n_b", "events_a", "events_b", "chi2", "p", "p_holm", "RMST a-b", "HR [95% CI]");
    out << line;
    for (const auto& t : events.tests) {
        if (t.milestone != milestone) continue;
        std::snprintf(line, sizeof line, "%-10s %-10s %4zu %4zu %8zu %8zu %8.4g %10.4g %10.4g %9.4g  %s\n",
                      std::string(to_string(t.a)).c_str(), std::string(to_string(t.b)).c_str(), t.n_a, t.n_b,
                      t.test.events_a, t.test.events_b, t.test.chi2, t.test.p, t.p_holm, t.rmst_a - t.rmst_b,
                      hazard_text(t).c_str());
        out << line;
    }
}

void write_events_csv(std::ostream& out, std::span<const RunEvents> runs, int generation) {
    out << "treatment,seed,event,generation,observed\n";
    for (const auto& run : runs) {
        for (Milestone m : kAll) {
            const auto [time, observed] = event_time(run, m, generation);
            out << to_string(run.treatment) << "," << run.seed << "," << to_string(m) << "," << time << ","
                << (observed ? 1 : 0) << "\n";
        }
    }
}

void write_logrank_csv(std::ostream& out, const CampaignEvents& events) {
    out << "treatment_a,treatment_b,event,n_a,n_b,events_a,events_b,chi2,p,p_holm\n";
    for (const auto& t : events.tests) {
        out << to_string(t.a) << "," << to_string(t.b) << "," << to_string(t.milestone) << "," << t.n_a << ","
            << t.n_b << "," << t.test.events_a << "," << t.test.events_b << "," << exact(t.test.chi2) << ","
            << exact(t.test.p) << "," << exact(t.p_holm) << "\n";
    }
}

void write_hazard_csv(std::ostream& out, const CampaignEvents& events) {
    out << "treatment_a,treatment_b,event,n_a,n_b,events_a,events_b,hazard_ratio,ci_low,ci_high,log_hr,se,"
           "p_wald,score_chi2,p_score,ties,rmst_a,rmst_b,rmst_difference,horizon,note\n";
    for (const auto& t : events.tests) {
        out << to_string(t.a) << "," << to_string(t.b) << "," << to_string(t.milestone) << "," << t.n_a << ","
            << t.n_b << "," << t.cox.events_a << "," << t.cox.events_b << ",";
        if (const auto& e = t.cox.estimate) {
            out << exact(e->hr) << "," << exact(e->ci_low) << "," << exact(e->ci_high) << ","
                << exact(e->log_hr) << "," << exact(e->se) << "," << exact(e->p) << ",";
        } else {
            out << ",,,,,,";
        }
        out << exact(t.cox.score_chi2) << "," << exact(t.cox.score_p) << "," << to_string(t.cox.ties) << ","
            << exact(t.rmst_a) << "," << exact(t.rmst_b) << "," << exact(t.rmst_a - t.rmst_b) << ","
            << events.generation << "," << hazard_note(t) << "\n";
    }
}

}  // namespace stepstone::runs
