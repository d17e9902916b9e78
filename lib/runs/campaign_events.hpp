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
#include "stats/cox.hpp"
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

/// How the hazard ratios of `stats` and `pool` treat tied event times
/// (docs/statistics.md: generations tie often, and Efron's approximation of the
/// exact partial likelihood is the closer one).
inline constexpr stats::Ties kHazardTies = stats::Ties::efron;

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
    /// Restricted mean time to the milestone over generations 0 to the chosen
    /// one: the area under `curve` up to it (stats::restricted_mean).
    double rmst = 0;
};

/// The log-rank test of two treatments on one milestone.
struct EventTest {
    Treatment a = Treatment::none, b = Treatment::none;
    Milestone milestone = Milestone::press;
    std::size_t n_a = 0, n_b = 0;
    stats::LogRank test;
    double p_holm = 1;  ///< Holm-adjusted over the pairs of this milestone
    /// The Cox hazard ratio of a (covariate 1) to b (0), kHazardTies.
    stats::CoxResult cox;
    double rmst_a = 0, rmst_b = 0;  ///< the two treatments' EventSummary::rmst
};

/// Why `test` has no hazard ratio, naming the treatments ("no events in sum
/// (HR -> 0)"); empty when it has one.
std::string hazard_note(const EventTest& test);

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

/// The text table of one milestone: per treatment the runs that reached it,
/// the Kaplan-Meier median (the midpoint median beside it where it differs)
/// and the RMST, then the log-rank tests with the RMST difference and the
/// hazard ratio and its CI.
void write_events_text(std::ostream& out, const CampaignEvents& events, Milestone milestone);
/// `treatment,seed,event,generation,observed`: every run and milestone
/// (observed 1 when reached at `generation`, 0 when censored there).
void write_events_csv(std::ostream& out, std::span<const RunEvents> runs, int generation);
/// `treatment_a,treatment_b,event,n_a,n_b,events_a,events_b,chi2,p,p_holm`.
void write_logrank_csv(std::ostream& out, const CampaignEvents& events);
/// One row per log-rank test, in its order: `treatment_a,treatment_b,event,n_a,
/// n_b,events_a,events_b,hazard_ratio,ci_low,ci_high,log_hr,se,p_wald,
/// score_chi2,p_score,ties,rmst_a,rmst_b,rmst_difference,horizon,note`; the
/// estimate's six columns empty and `note` saying why when there is none.
void write_hazard_csv(std::ostream& out, const CampaignEvents& events);

}  // namespace stepstone::runs
