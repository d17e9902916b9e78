#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <ostream>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "runs/treatment.hpp"
#include "stats/survival.hpp"

namespace stepstone::runs {

/// The steps of the task whose first occurrence in a run is an event
/// (docs/statistics.md: endpoints), in task order.
enum class Milestone { press, pickup, release, ball };
inline constexpr std::size_t kMilestones = 4;

/// Every milestone, in task order.
std::span<const Milestone> all_milestones();
/// "press", "pickup", "release", "ball".
std::string_view to_string(Milestone m);
/// Parses a milestone name; ConfigError naming `what` and the valid names otherwise.
Milestone parse_milestone(std::string_view name, std::string_view what);

/// First generation (up to the chosen one) in which any evaluated policy of a
/// run reached each milestone, absent when none did.
using FirstEvents = std::array<std::optional<int>, kMilestones>;

/// The Kaplan-Meier summary of one treatment and milestone.
struct EventSummary {
    Treatment treatment = Treatment::none;
    Milestone milestone = Milestone::press;
    std::size_t runs = 0;
    std::size_t reached = 0;  ///< runs that reached it by the chosen generation
    stats::KaplanMeier curve;
};

/// The log-rank test of two treatments on one milestone.
struct EventTest {
    Treatment a = Treatment::none, b = Treatment::none;
    Milestone milestone = Milestone::press;
    std::size_t n_a = 0, n_b = 0;
    stats::LogRank test;
    double p_holm = 1;  ///< Holm-adjusted over the pairs of this milestone
};

/// The time-to-event statistics of a campaign: one event time per run and
/// milestone, right-censored at the chosen generation.
struct CampaignEvents {
    int generation = 0;
    std::vector<Treatment> treatments;    ///< in campaign order
    std::vector<EventSummary> summaries;  ///< milestone-major, treatments in order
    std::vector<EventTest> tests;         ///< milestone-major, every pair (a before b in campaign order)
};

/// One run's event times as the statistics take them.
struct RunEvents {
    Treatment treatment = Treatment::none;
    std::uint64_t seed = 0;
    FirstEvents first;
};

/// Kaplan-Meier curves and pairwise log-rank tests (Holm per milestone) from
/// the runs' first events, censored at `generation`. `treatments` gives the order.
CampaignEvents campaign_events(std::span<const RunEvents> runs, std::span<const Treatment> treatments,
                               int generation);

/// The text table of one milestone: per treatment the runs that reached it
/// and the Kaplan-Meier median, then the log-rank tests.
void write_events_text(std::ostream& out, const CampaignEvents& events, Milestone milestone);
/// `treatment,seed,event,generation,observed`: every run and milestone
/// (observed 1 when reached at `generation`, 0 when censored there).
void write_events_csv(std::ostream& out, std::span<const RunEvents> runs, int generation);
/// `treatment_a,treatment_b,event,n_a,n_b,events_a,events_b,chi2,p,p_holm`.
void write_logrank_csv(std::ostream& out, const CampaignEvents& events);

}  // namespace stepstone::runs
