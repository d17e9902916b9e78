#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "db/connection.hpp"
#include "runs/campaign_events.hpp"

namespace stepstone::runs {

// A run file's series along generations, as the report's figures and the
// service's API read them.

/// One generation of a run: its survivors' rewards and its policies' r_max.
struct GenerationPoint {
    int generation = 0;
    double best = 0.0;                   ///< best task reward among the survivors
    double median = 0.0;                 ///< median task reward among the survivors
    std::optional<double> mean_r_max;    ///< mean r_max of the policies evaluated then
    std::optional<double> max_r_max;     ///< largest r_max of the policies evaluated then
};

/// The generation table of run `run_id`, in generation order.
std::vector<GenerationPoint> load_generations(db::Connection& connection, std::int64_t run_id);

/// The policies of one generation of a run that reached each milestone.
struct MilestoneCounts {
    int generation = 0;
    std::int64_t policies = 0;
    std::array<std::int64_t, kMilestones> reached{};  ///< in all_milestones() order

    /// reached[m] / policies (0 without policies).
    double share(std::size_t m) const;
};

/// The milestone counts of every generation of run `run_id` (schema 0005
/// files; check db::has_milestones first).
std::vector<MilestoneCounts> load_milestone_counts(db::Connection& connection, std::int64_t run_id);

}  // namespace stepstone::runs
