#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "db/connection.hpp"
#include "report/canvas.hpp"
#include "runs/campaign_events.hpp"
#include "runs/treatment.hpp"

namespace stepstone::report {

/// The policies of one generation of a run that reached each milestone.
struct MilestoneCounts {
    int generation = 0;
    std::int64_t policies = 0;
    std::array<std::int64_t, runs::kMilestones> reached{};  ///< in runs::all_milestones() order

    /// reached[m] / policies (0 without policies).
    double share(std::size_t m) const;
};

/// The milestone counts of every generation of run `run_id` (schema 0005
/// files; check db::has_milestones first).
std::vector<MilestoneCounts> load_milestone_counts(db::Connection& connection, std::int64_t run_id);

/// Size of the two-by-two milestone figures.
inline constexpr int kPanelFigureWidth = 1000;
inline constexpr int kPanelFigureHeight = 980;

/// Kaplan-Meier curves of the time to each milestone, one panel per
/// milestone: per treatment the share of runs that have not reached it yet,
/// as a step curve, censored runs marked with a tick, and the runs at risk at
/// each x tick in a table under the axis.
void draw_kaplan_meier(Canvas& canvas, const runs::CampaignEvents& events);

/// One panel per milestone: per treatment, the median over seeds of the share
/// of each generation's policies that reached it. `series[t][r]` is run r of
/// treatment t.
void draw_milestone_shares(Canvas& canvas, std::span<const runs::Treatment> treatments,
                           std::span<const std::vector<std::vector<MilestoneCounts>>> series);

/// One run: the share of each generation's policies that reached each milestone.
void draw_run_milestones(Canvas& canvas, std::span<const MilestoneCounts> counts, const std::string& title);

}  // namespace stepstone::report
