#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "report/canvas.hpp"
#include "runs/campaign_events.hpp"
#include "runs/run_series.hpp"
#include "runs/treatment.hpp"

namespace stepstone::report {

/// The milestones of one generation of a run (runs::load_milestone_counts).
using runs::MilestoneCounts;

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
