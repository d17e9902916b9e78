// Milestone figures: Kaplan-Meier curves of the time to each milestone, and
// the share of policies reaching each milestone along generations.

#include "report/event_figures.hpp"

#include <cairo.h>

#include <algorithm>

#include "core/text.hpp"
#include "report/chart.hpp"
#include "report/figures.hpp"
#include "stats/summary.hpp"

namespace stepstone::report {

namespace {

constexpr double kTableRow = 15.0;
constexpr double kTableSize = 11.0;

std::string milestone_title(runs::Milestone m) {
    switch (m) {
        case runs::Milestone::press:
            return "switch pressed";
        case runs::Milestone::pickup:
            return "ball picked up";
        case runs::Milestone::release:
            return "released at the basket";
        case runs::Milestone::ball:
            return "ball collected";
    }
    return "";
}

// the {x, y, width, height} of panel k of a two-by-two figure
std::array<double, 4> panel(const Canvas& canvas, std::size_t k) {
    const double w = canvas.width() / 2.0;
    const double h = canvas.height() / 2.0;
    return {w * static_cast<double>(k % 2), h * static_cast<double>(k / 2), w, h};
}

std::vector<std::pair<std::string, Colour>> legend_of(std::span<const runs::Treatment> treatments) {
    std::vector<std::pair<std::string, Colour>> entries;
    for (auto t : treatments) entries.emplace_back(std::string(runs::to_string(t)), treatment_colour(t));
    return entries;
}

}  // namespace

namespace {

// The legend goes in the right-hand corner that fewer curves cross over the
// last 40% of the generations: the top one when curves have dropped below 3/4
// by then, the bottom one when they stay above 1/4 (ties: the top).
bool legend_below(const runs::CampaignEvents& events, runs::Milestone m) {
    const double from = 0.6 * static_cast<double>(events.generation);
    int top = 0, bottom = 0;
    for (const auto& s : events.summaries) {
        if (s.milestone != m) continue;
        if (s.curve.at(from) >= 0.75) ++top;
        if (s.curve.at(static_cast<double>(events.generation)) <= 0.25) ++bottom;
    }
    return bottom < top;
}

}  // namespace

void draw_kaplan_meier(Canvas& canvas, const runs::CampaignEvents& events) {
    canvas.fill(kWhite);
    const double g = std::max(events.generation, 1);
    const auto legend = legend_of(events.treatments);
    const double table = kTableRow * static_cast<double>(events.treatments.size() + 1);
    for (std::size_t k = 0; k < runs::kMilestones; ++k) {
        const runs::Milestone m = runs::all_milestones()[k];
        ChartFrame frame{concat("first ", milestone_title(m)), "generation", "runs that have not reached it",
                         std::pair{0.0, g}, std::pair{0.0, 1.0}};
        frame.region = panel(canvas, k);
        frame.below = table;
        Chart chart(canvas, frame, 0.0, g, 0.0, 1.0);
        cairo_t* cr = canvas.cr();
        std::size_t row = 0;
        for (const auto& s : events.summaries) {
            if (s.milestone != m) continue;
            const Colour colour = treatment_colour(s.treatment);
            // the step curve from S = 1 at generation 0 to the last follow-up
            Curve curve{"", colour, {0.0}, {1.0}, {}, {}, false, true};
            // earlier treatments drawn wider, so curves that coincide stay visible beneath later ones
            curve.width = 2.0 + 2.2 * static_cast<double>(events.treatments.size() - 1 - row);
            for (const auto& step : s.curve.steps) {
                if (step.events == 0) continue;
                curve.x.push_back(step.time);
                curve.y.push_back(step.survival);
            }
            double last = 0.0;
            for (const auto& step : s.curve.steps) last = std::max(last, step.time);
            curve.x.push_back(last);
            curve.y.push_back(curve.y.back());
            chart.curve(curve);
            // censored runs: a tick on the curve, and a hover note with their count
            chart.clip();
            canvas.set_colour(colour);
            cairo_set_line_width(cr, 2.0);
            for (const auto& step : s.curve.steps) {
                if (step.censored == 0) continue;
                const double x = chart.px(step.time) - (step.time >= g ? 3.0 : 0.0);
                const double y = chart.py(s.curve.at(step.time));
                cairo_move_to(cr, x, y - 8.0);
                cairo_line_to(cr, x, y + 8.0);
                canvas.hover(
                    x, y, 6.0,
                    concat(runs::to_string(s.treatment), ": ", step.censored, " censored at ", step.time));
            }
            cairo_stroke(cr);
            chart.release_clip();
            // the runs at risk at every x tick, under the axis label
            const double y = chart.bottom() + 58.0 + kTableRow * static_cast<double>(row + 1);
            canvas.text(chart.left() - 10.0, y, std::string(runs::to_string(s.treatment)), kTableSize - 1.0,
                        colour, 1.0, 0.5);
            for (const double v : chart.x_ticks().values) {
                if (v < 0 || v > g) continue;
                canvas.text(chart.px(v), y, concat(s.curve.at_risk(v)), kTableSize, colour, 0.5, 0.5);
            }
            ++row;
        }
        canvas.text(chart.left() - 10.0, chart.bottom() + 58.0, "at risk", kTableSize, kGrey, 1.0, 0.5);
        chart.legend(legend, true, legend_below(events, m));
    }
}

void draw_milestone_shares(Canvas& canvas, std::span<const runs::Treatment> treatments,
                           std::span<const std::vector<std::vector<MilestoneCounts>>> series) {
    canvas.fill(kWhite);
    int last = 1;
    for (const auto& runs : series) {
        for (const auto& run : runs) {
            if (!run.empty()) last = std::max(last, run.back().generation);
        }
    }
    for (std::size_t k = 0; k < runs::kMilestones; ++k) {
        std::vector<Curve> curves;
        double top = 0.0;
        for (std::size_t t = 0; t < treatments.size(); ++t) {
            Curve curve{std::string(runs::to_string(treatments[t])),
                        treatment_colour(treatments[t]),
                        {},
                        {},
                        {},
                        {},
                        false,
                        false};
            for (int gen = 0; gen <= last; ++gen) {
                std::vector<double> shares;
                for (const auto& run : series[t]) {
                    if (static_cast<std::size_t>(gen) < run.size())
                        shares.push_back(run[static_cast<std::size_t>(gen)].share(k));
                }
                if (shares.empty()) continue;
                const auto s = stats::summarize(shares);
                curve.x.push_back(gen);
                curve.y.push_back(s.median);
                curve.low.push_back(s.q1);
                curve.high.push_back(s.q3);
                top = std::max(top, s.q3);
            }
            curves.push_back(std::move(curve));
        }
        ChartFrame frame{concat(milestone_title(runs::all_milestones()[k]), ": share of policies"),
                         "generation", "share of the generation's policies",
                         std::pair{0.0, static_cast<double>(last)}, std::pair{0.0, std::max(top, 0.01)}};
        frame.region = panel(canvas, k);
        Chart chart(canvas, frame, 0.0, last, 0.0, std::max(top, 0.01));
        std::vector<std::pair<std::string, Colour>> legend;
        for (const auto& c : curves) {
            chart.curve(c);
            legend.emplace_back(c.name, c.colour);
        }
        chart.legend(legend, true);
    }
}

void draw_run_milestones(Canvas& canvas, std::span<const MilestoneCounts> counts, const std::string& title) {
    std::vector<Curve> curves;
    const Colour colours[] = {kGreen, kOrange, kPurple, kBlue};
    for (std::size_t k = 0; k < runs::kMilestones; ++k) {
        Curve curve{milestone_title(runs::all_milestones()[k]), colours[k], {}, {}, {}, {}, false, false};
        for (const auto& c : counts) {
            curve.x.push_back(c.generation);
            curve.y.push_back(c.share(k));
        }
        curves.push_back(std::move(curve));
    }
    line_chart(canvas, {title, "generation", "share of the generation's policies", {}, std::pair{0.0, 1.0}},
               curves);
}

}  // namespace stepstone::report
