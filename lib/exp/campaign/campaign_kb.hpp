#pragma once

#include <filesystem>
#include <vector>

#include "db/connection.hpp"
#include "runs/campaign_config.hpp"
#include "runs/campaign_store.hpp"

namespace stepstone::exp {

/// Writes the gzip file `in` uncompressed to `out` (a shipped KB such as
/// examples/fixtures/demo_kb.db.gz). Throws DataError naming `in` when it is
/// not whole gzip data, Error when `out` cannot be written.
void gunzip_file(const std::filesystem::path& in, const std::filesystem::path& out);

/// The campaign's KB step: makes kb/kb.db in `dir` (export of the best
/// source run, merge of all, or a copy of kb.file; coarsened to kb.delta),
/// its randomized twin when a treatment needs it, and records both in
/// campaign.db through `connection`. `runs` holds the finished source runs.
void make_campaign_kbs(const std::filesystem::path& dir, const runs::CampaignConfig& config,
                       db::Connection& connection, const std::vector<runs::CampaignRun>& runs);

/// The source run with the highest best reward, the lowest seed on ties (the
/// KB of kb.from best, the seeds of seed.from best). `runs` holds the
/// finished source runs, at least one.
const runs::CampaignRun& best_source_run(const std::vector<runs::CampaignRun>& runs);

/// The run file that seeds the seeded treatments: seed.file, or the best
/// source run's file under `dir`.
std::filesystem::path campaign_seed_source(const std::filesystem::path& dir,
                                           const runs::CampaignConfig& config,
                                           const std::vector<runs::CampaignRun>& runs);

}  // namespace stepstone::exp
