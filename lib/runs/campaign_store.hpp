#pragma once

#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "db/connection.hpp"
#include "runs/campaign_config.hpp"

namespace stepstone::runs {

// campaign.db: the campaign's config and one row per planned run (its status,
// progress, best reward, digest and error), written by the campaign process
// only. The run files themselves are written by their own `evolve`.

/// campaign.db's name in a campaign directory.
inline constexpr const char* kCampaignFile = "campaign.db";
/// The campaign's KB and its randomized twin, relative to the campaign directory.
inline constexpr const char* kKbFile = "kb/kb.db";
inline constexpr const char* kRandomKbFile = "kb/kb-rand.db";

/// A run as campaign.db lists it: its plan and where it stands.
struct IndexedRun {
    PlannedRun run;
    RunStatus status = RunStatus::pending;
};

/// Where a campaign's runs and KBs are, read from campaign.db.
struct CampaignIndex {
    nlohmann::json config;
    std::vector<IndexedRun> runs;  ///< in plan order
};
/// Reads campaign.db of `dir`; throws DatabaseError / DataError naming the file.
CampaignIndex load_campaign(const std::filesystem::path& dir);

/// Writes a new campaign.db at `path` (moved into place whole): the config
/// and one pending row per planned run, ids 1.. in plan order.
void create_campaign_db(const std::filesystem::path& path, const CampaignConfig& config,
                        const std::vector<PlannedRun>& plan);

/// One run of campaign.db as the campaign process tracks it.
struct RunState {
    PlannedRun run;
    std::int64_t id = 0;
    RunStatus status = RunStatus::pending;
    int generations_done = -1;
    std::optional<double> best_reward;
};

/// The runs of `index` as states, ids 1.. in order.
std::vector<RunState> run_states(const CampaignIndex& index);

/// What a run file says about itself.
struct RunFileState {
    bool finished = false;
    int generations_done = -1;
    double best_reward = 0;
};

/// Reads the run file at `path`; nullopt when it does not exist. Throws
/// DatabaseError when it cannot be read.
std::optional<RunFileState> read_run_file(const std::filesystem::path& path);

/// Writes `state`'s status, progress and best reward, with `digest`,
/// `wall_time` and `error`, to its campaign_run row.
void update_run_row(db::Connection& connection, const RunState& state,
                    const std::optional<std::string>& digest, double wall_time,
                    const std::optional<std::string>& error);

/// Records (or replaces) the KB `name` stored at `file` (relative to the
/// campaign directory; read at `path`) with how it was made, its size and digest.
void record_kb(db::Connection& connection, const std::string& name, const std::string& file,
               const std::string& made_from, const std::filesystem::path& path);

}  // namespace stepstone::runs
