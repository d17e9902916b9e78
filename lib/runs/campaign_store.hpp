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

/// A run of a campaign as campaign.db holds it: its plan and where it stands.
/// The one model of a campaign's run, for the campaign process that updates
/// it and for the statistics, the report and the service that read it.
struct CampaignRun {
    PlannedRun run;
    std::int64_t id = 0;  ///< its row, 1.. in plan order
    RunStatus status = RunStatus::pending;
    int generations_done = -1;          ///< as last recorded (-1: none)
    std::optional<double> best_reward;  ///< as last recorded
    std::string digest;                 ///< of a finished run; empty otherwise
    double wall_time = 0;               ///< seconds its last attempt took
    std::string error;                  ///< why it failed; empty otherwise
};

/// A campaign's config and runs, read from campaign.db.
struct CampaignIndex {
    nlohmann::json config;
    std::vector<CampaignRun> runs;  ///< in plan order
};
/// Reads campaign.db of `dir`; throws DatabaseError / DataError naming the file.
CampaignIndex load_campaign(const std::filesystem::path& dir);
/// Reads an open campaign.db.
CampaignIndex load_campaign(db::Connection& connection);

/// Opens campaign.db at `path` for writing once: a campaign killed in the middle of a write
/// leaves a hot journal that only a writer can roll back, before read-only loads.
void recover_campaign_db(const std::filesystem::path& path);

/// A knowledge base a campaign made ('kb' and 'kb-rand'), as campaign.db records it.
struct CampaignKb {
    std::string name;
    std::string file;  ///< relative to the campaign directory
    std::string made_from;
    std::string digest;  ///< its content digest
    std::int64_t segments = 0;
};
/// The KBs an open campaign.db records, by name.
std::vector<CampaignKb> load_campaign_kbs(db::Connection& connection);

/// Writes a new campaign.db at `path` (moved into place whole): the config
/// and one pending row per planned run, ids 1.. in plan order.
void create_campaign_db(const std::filesystem::path& path, const CampaignConfig& config,
                        const std::vector<PlannedRun>& plan);

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
void update_run_row(db::Connection& connection, const CampaignRun& state,
                    const std::optional<std::string>& digest, double wall_time,
                    const std::optional<std::string>& error);

/// Records (or replaces) the KB `name` stored at `file` (relative to the
/// campaign directory; read at `path`) with how it was made, its size and digest.
void record_kb(db::Connection& connection, const std::string& name, const std::string& file,
               const std::string& made_from, const std::filesystem::path& path);

}  // namespace stepstone::runs
