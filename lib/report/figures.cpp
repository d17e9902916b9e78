// Reward, shaping, knowledge-base and campaign figures.

#include "report/figures.hpp"

#include <algorithm>
#include <map>

#include "core/text.hpp"
#include "report/chart.hpp"
#include "stats/summary.hpp"

namespace stepstone::report {

namespace {

// the median of `values` at x, with the quartiles as the band (nothing for no values)
void add_quartiles(Curve& curve, double x, std::span<const double> values) {
    if (values.empty()) return;
    const auto s = stats::summarize(values);
    curve.x.push_back(x);
    curve.y.push_back(s.median);
    curve.low.push_back(s.q1);
    curve.high.push_back(s.q3);
}

}  // namespace

Colour treatment_colour(runs::Treatment treatment) {
    switch (treatment) {
        case runs::Treatment::none:
            return kBlack;
        case runs::Treatment::sum:
            return kBlue;
        case runs::Treatment::mo:
            return kVermillion;
        case runs::Treatment::sum_rand:
            return kSkyBlue;
        case runs::Treatment::mo_rand:
            return kOrange;
        // the seeded twins: the palette's other colours
        case runs::Treatment::seed:
            return kGreen;
        case runs::Treatment::seed_sum:
            return kPurple;
        case runs::Treatment::seed_mo:
            return kYellow;
        case runs::Treatment::seed_sum_rand:
            return kGrey;
        case runs::Treatment::seed_mo_rand:
            return kDoor;
    }
    return kGrey;
}

void draw_run_rewards(Canvas& canvas, std::span<const GenerationPoint> generations, const std::string& title) {
    Curve best{"best", kBlue, {}, {}, {}, {}, false, false};
    Curve median{"median", kVermillion, {}, {}, {}, {}, false, false};
    for (const auto& g : generations) {
        best.x.push_back(g.generation);
        best.y.push_back(g.best);
        median.x.push_back(g.generation);
        median.y.push_back(g.median);
    }
    const Curve curves[] = {best, median};
    line_chart(canvas, {title, "generation", "task reward of the survivors (balls / 24)", {}, {}}, curves);
}

void draw_run_shaping(Canvas& canvas, std::span<const GenerationPoint> generations, const std::string& title) {
    Curve mean{"mean r_max", kGreen, {}, {}, {}, {}, false, false};
    Curve max{"largest r_max", kPurple, {}, {}, {}, {}, true, false};
    for (const auto& g : generations) {
        if (!g.mean_r_max) continue;
        mean.x.push_back(g.generation);
        mean.y.push_back(*g.mean_r_max);
        max.x.push_back(g.generation);
        max.y.push_back(g.max_r_max.value_or(0.0));
    }
    const Curve curves[] = {mean, max};
    line_chart(canvas, {title, "generation", "r_max of the evaluated policies (KB average reward)", {}, {}}, curves);
}

void draw_kb_histogram(Canvas& canvas, const kb::KnowledgeBase& kb, const std::string& title, int bins,
                       bool nonzero_only) {
    bins = std::max(bins, 1);
    const double top = kb.max_average() > 0.0 ? kb.max_average() : 1.0;
    std::vector<double> edges, counts(static_cast<std::size_t>(bins), 0.0);
    for (int i = 0; i <= bins; ++i) edges.push_back(top * i / bins);
    for (const auto& record : kb.records()) {
        if (nonzero_only && !(record.average() > 0.0)) continue;
        const double t = std::clamp(record.average() / top, 0.0, 1.0);
        counts[std::min(static_cast<std::size_t>(t * bins), static_cast<std::size_t>(bins - 1))] += 1.0;
    }
    ChartFrame frame{title, "average reward of the segment", "segments", std::pair{0.0, top}, {}};
    histogram_chart(canvas, frame, edges, counts, kBlue);
}

void draw_kb_growth(Canvas& canvas, const kb::KnowledgeBase& kb, const std::string& title) {
    // segments inserted per (source, generation), in observation order
    std::map<std::pair<std::uint32_t, std::int64_t>, std::size_t> inserted;
    for (const auto& record : kb.records()) ++inserted[{record.first.source, record.first.generation}];
    Curve size{"", kBlue, {}, {}, {}, {}, false, false};
    const bool one_source = kb.sources().size() <= 1;
    double total = 0.0, index = 0.0;
    for (const auto& [key, count] : inserted) {
        total += static_cast<double>(count);
        size.x.push_back(one_source ? static_cast<double>(key.second) : index);
        size.y.push_back(total);
        index += 1.0;
    }
    ChartFrame frame{title, one_source ? "observed generation" : "observation (sources in merge order)",
                     "segments in the knowledge base", {}, {}};
    line_chart(canvas, frame, std::span<const Curve>(&size, 1));
}

void draw_treatment_rewards(Canvas& canvas, const runs::CampaignStats& stats) {
    std::vector<Curve> curves;
    const auto generations = static_cast<std::size_t>(stats.generation) + 1;
    for (const auto& t : stats.treatments) {
        Curve c{std::string(runs::to_string(t.treatment)),
                treatment_colour(t.treatment),
                {},
                {},
                {},
                {},
                false,
                false};
        for (std::size_t g = 0; g < generations; ++g) {
            std::vector<double> values;
            for (const auto& run : stats.runs) {
                if (run.treatment == t.treatment && g < run.best.size()) values.push_back(run.best[g]);
            }
            add_quartiles(c, static_cast<double>(g), values);
        }
        curves.push_back(std::move(c));
    }
    line_chart(canvas,
               {"Best-so-far task reward per treatment: median over seeds, quartile band", "generation",
                "best task reward so far (balls / 24)", {}, {}},
               curves);
}

void draw_successes(Canvas& canvas, const runs::CampaignStats& stats) {
    std::vector<Curve> curves;
    std::size_t most = 1;
    for (std::size_t t = 0; t < stats.treatments.size(); ++t) {
        const auto treatment = stats.treatments[t].treatment;
        Curve c{std::string(runs::to_string(treatment)),
                treatment_colour(treatment),
                {},
                {},
                {},
                {},
                false,
                true};
        for (std::size_t g = 0; g < stats.successes.size(); ++g) {
            c.x.push_back(static_cast<double>(g));
            c.y.push_back(static_cast<double>(stats.successes[g][t]));
        }
        most = std::max(most, stats.treatments[t].best.size());
        curves.push_back(std::move(c));
    }
    ChartFrame frame{concat("Successful runs per treatment (best-of-run reward >= ", stats.threshold, ")"),
                     "generation", "successful runs", {}, std::pair{0.0, static_cast<double>(most)}};
    line_chart(canvas, frame, curves);
}

void draw_best_of_run(Canvas& canvas, const runs::CampaignStats& stats) {
    std::vector<Strip> strips;
    for (const auto& t : stats.treatments) {
        strips.push_back({std::string(runs::to_string(t.treatment)), treatment_colour(t.treatment), t.best});
    }
    ChartFrame frame{concat("Best-of-run task reward at generation ", stats.generation, " (one point per run)"),
                     "treatment", "best-of-run task reward (balls / 24)", {}, {}};
    strip_chart(canvas, frame, strips, stats.threshold);
}

namespace {

// per treatment, the median over its runs (and the quartile band) of one
// value of each generation; runs or generations without it are skipped
template <class Value>
void treatment_series(Canvas& canvas, std::span<const runs::Treatment> treatments,
                      std::span<const std::vector<std::vector<GenerationPoint>>> series,
                      const ChartFrame& frame, Value value) {
    std::vector<Curve> curves;
    for (std::size_t t = 0; t < treatments.size() && t < series.size(); ++t) {
        Curve c{std::string(runs::to_string(treatments[t])),
                treatment_colour(treatments[t]),
                {},
                {},
                {},
                {},
                false,
                false};
        std::size_t length = 0;
        for (const auto& run : series[t]) length = std::max(length, run.size());
        for (std::size_t g = 0; g < length; ++g) {
            std::vector<double> values;
            for (const auto& run : series[t]) {
                if (g >= run.size()) continue;
                if (const std::optional<double> v = value(run[g])) values.push_back(*v);
            }
            add_quartiles(c, static_cast<double>(g), values);
        }
        if (!c.x.empty()) curves.push_back(std::move(c));
    }
    line_chart(canvas, frame, curves);
}

}  // namespace

void draw_treatment_shaping(Canvas& canvas, std::span<const runs::Treatment> treatments,
                            std::span<const std::vector<std::vector<GenerationPoint>>> series) {
    treatment_series(canvas, treatments, series,
                     {"Shaping signal: mean r_max / A of each generation's policies, median over seeds",
                      "generation",
                      "mean r_max / A (A: the KB's largest average)",
                      {},
                      {}},
                     [](const GenerationPoint& g) { return g.mean_r_max; });
}

void draw_treatment_medians(Canvas& canvas, std::span<const runs::Treatment> treatments,
                            std::span<const std::vector<std::vector<GenerationPoint>>> series) {
    treatment_series(canvas, treatments, series,
                     {"Median survivor reward per treatment: median over seeds, quartile band", "generation",
                      "median survivor reward (balls / 24)", {}, {}},
                     [](const GenerationPoint& g) { return std::optional<double>(g.median); });
}

}  // namespace stepstone::report
