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

}  // namespace

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
    std::snprintf(line, sizeof line, "%-10s %5s %8s %14s\n", "treatment", "runs", "reached", "median (KM)");
    out << line;
    for (const auto& s : events.summaries) {
        if (s.milestone != milestone) continue;
        const std::string median = s.curve.median ? concat(*s.curve.median) : "not reached";
        std::snprintf(line, sizeof line, "%-10s %5zu %8zu %14s\n",
                      std::string(to_string(s.treatment)).c_str(), s.runs, s.reached, median.c_str());
        out << line;
    }
    const auto pairs = std::count_if(events.tests.begin(), events.tests.end(),
                                     [&](const EventTest& t) { return t.milestone == milestone; });
    if (pairs == 0) return;
    out << "\nlog-rank, time to first " << to_string(milestone)
        << " (p: chi-square with 1 df; p_holm: over the " << pairs << " pairs)\n";
    std::snprintf(line, sizeof line, "%-10s %-10s %4s %4s %8s %8s %8s %10s %10s\n", "a", "b", "n_a", "n_b",
                  "events_a", "events_b", "chi2", "p", "p_holm");
    out << line;
    for (const auto& t : events.tests) {
        if (t.milestone != milestone) continue;
        std::snprintf(line, sizeof line, "%-10s %-10s %4zu %4zu %8zu %8zu %8.4g %10.4g %10.4g\n",
                      std::string(to_string(t.a)).c_str(), std::string(to_string(t.b)).c_str(), t.n_a, t.n_b,
                      t.test.events_a, t.test.events_b, t.test.chi2, t.test.p, t.p_holm);
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

}  // namespace stepstone::runs
