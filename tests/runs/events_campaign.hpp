#pragma once

// A tiny campaign whose milestones are set by hand, for the time-to-event
// statistics of `stats` (campaign_events_test.cpp) and of `pool`
// (pooled_stats_test.cpp).

#include <filesystem>

#include "support/temp_dir.hpp"

namespace stepstone::runstest {

/// The shipped KB fixture, then none and sum x 3 seeds x 4 generations,
/// population 8, made by `stepstone campaign` into dir/camp. Then every
/// individual's milestones are cleared and set again by hand: presses at
/// generation 0 in every run; pickups none {3, never, never}, sum {0, 1, 4};
/// one ball, sum seed 3 at generation 4; no release.
struct EventsCampaign {
    test::TempDir dir;
    std::filesystem::path camp = dir / "camp";
    EventsCampaign();
};

}  // namespace stepstone::runstest
