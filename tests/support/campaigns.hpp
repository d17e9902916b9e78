#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

namespace stepstone::test {

// A tiny campaign for the tests of the campaign engine (tests/exp/campaign)
// and of its statistics (tests/runs/campaign_stats_test.cpp).

/// The config of a tiny campaign: one source run (seed 4, 3 generations,
/// population 8, one 200-step start, a KB of width 20 and delta 1.83 observed
/// every generation), the KB of the best source run and its randomized twin
/// (seed 9), then the five treatments x 2 seeds of `target_generations`
/// generations of one `steps`-step start (population 8): 11 runs.
std::string tiny_campaign_json(int target_generations, int steps = 200);

/// `stepstone campaign dir/c.json --dir dir/name --quiet` followed by `extra`.
CliResult run_campaign(const TempDir& dir, const std::string& name, const std::vector<std::string>& extra);

/// Copies into `to` (which must not exist) the folder of a finished tiny campaign of
/// `target_generations` (tiny_campaign_json, --jobs 2). The campaign runs once per test
/// process and config, so the sections of a test case, each of which restarts the case,
/// damage their own copy instead of running it again. Throws if the campaign fails.
void copy_tiny_campaign(const std::filesystem::path& to, int target_generations);

/// campaign_run.id -> digest of the runs that campaign.db of `dir` records finished.
std::map<std::int64_t, std::string> finished_digests(const std::filesystem::path& dir);

/// How many runs campaign.db of `dir` records finished (0 while it cannot be read):
/// for polling a campaign that is still starting or running.
std::int64_t finished_runs(const std::filesystem::path& dir);

/// How many runs campaign.db of `dir` records finished, once the campaign's process
/// has ended: an open that fails is tried again for up to 10 s (the first reader after
/// a SIGKILL recovers the WAL the process left, and may meet a stray run's process),
/// then the last error is thrown. Never 0 for a file it could not read.
std::int64_t finished_runs_after_exit(const std::filesystem::path& dir);

}  // namespace stepstone::test
