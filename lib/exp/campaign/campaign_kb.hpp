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

}  // namespace stepstone::exp
