#pragma once

#include <cstdint>
#include <ostream>

#include "runs/campaign_config.hpp"

namespace stepstone::exp {

/// The campaign's cost, as printed by --dry-run.
struct CampaignCost {
    std::int64_t runs = 0;
    std::int64_t evaluations = 0;  ///< policy evaluations over every run
    double robot_steps = 0;        ///< upper bound: every evaluation runs its full episode
    double steps_per_second = 0;   ///< one core, measured now on full-length random policies
    double cpu_seconds = 0;        ///< robot_steps / steps_per_second
};

/// Counts evaluations and robot steps and times the simulator for a moment
/// (about `measure_seconds`) to turn them into a CPU-time upper bound.
CampaignCost estimate_cost(const runs::CampaignConfig& config, double measure_seconds = 0.3);

/// The run files of a campaign directory and what they hold, as a text table.
void write_plan(std::ostream& out, const runs::CampaignConfig& config, const CampaignCost& cost,
                unsigned jobs);

}  // namespace stepstone::exp
