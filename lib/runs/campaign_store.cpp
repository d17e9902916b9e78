#include "runs/campaign_store.hpp"

#include "core/error.hpp"
#include "core/text.hpp"
#include "db/database.hpp"
#include "db/digest.hpp"
#include "db/kb_store.hpp"
#include "runs/run_store.hpp"

namespace stepstone::runs {

namespace fs = std::filesystem;

CampaignIndex load_campaign(const fs::path& dir) {
    const fs::path path = dir / kCampaignFile;
    if (!fs::exists(path)) {
        const bool demo = fs::exists(dir / "campaign" / kCampaignFile);
        throw DataError(concat(dir.string(), ": no campaign here (", kCampaignFile, " is missing)",
                               demo ? concat("; the campaign is in ", (dir / "campaign").string()) : ""));
    }
    auto connection = db::open_database(path, db::OpenMode::read_only);
    return load_campaign(connection);
}

CampaignIndex load_campaign(db::Connection& connection) {
    const std::string& path = connection.name();
    CampaignIndex index;
    auto config = connection.prepare(db::sql("campaign/select_config.sql"));
    if (!config.step()) throw DataError(concat(path, ": holds no campaign"));
    try {
        index.config = nlohmann::json::parse(config.column_text(0));
    } catch (const nlohmann::json::exception& e) {
        throw DataError(concat(path, ": the stored campaign config is malformed: ", one_line(e.what())));
    }
    auto rows = connection.prepare(db::sql("campaign/select_runs.sql"));
    const int id = rows.column("id"), step = rows.column("step"), treatment = rows.column("treatment"),
              seed = rows.column("seed"), file = rows.column("file"),
              generations = rows.column("generations"), status = rows.column("status"),
              done = rows.column("generations_done"), best = rows.column("best_reward"),
              digest = rows.column("digest"), wall_time = rows.column("wall_time"),
              error = rows.column("error");
    while (rows.step()) {
        CampaignRun r;
        r.id = rows.column_int(id);
        r.run.step = parse_campaign_step(rows.column_text(step), path + ": campaign_run.step");
        r.run.treatment = parse_treatment(rows.column_text(treatment), "campaign_run.treatment");
        r.run.seed = static_cast<std::uint64_t>(rows.column_int(seed));
        r.run.file = rows.column_text(file);
        r.run.generations = static_cast<int>(rows.column_int(generations));
        r.status = parse_run_status(rows.column_text(status), path + ": campaign_run.status");
        r.generations_done = static_cast<int>(rows.column_int(done));
        if (!rows.is_null(best)) r.best_reward = rows.column_double(best);
        if (!rows.is_null(digest)) r.digest = rows.column_text(digest);
        r.wall_time = rows.column_double(wall_time);
        if (!rows.is_null(error)) r.error = rows.column_text(error);
        index.runs.push_back(std::move(r));
    }
    return index;
}

void recover_campaign_db(const fs::path& path) {
    db::open_database(path, db::OpenMode::read_write).query_int(db::sql("campaign/count.sql"));
}

std::vector<CampaignKb> load_campaign_kbs(db::Connection& connection) {
    auto rows = connection.prepare(db::sql("campaign/select_kbs.sql"));
    std::vector<CampaignKb> out;
    const int name = rows.column("name"), file = rows.column("file"), made_from = rows.column("made_from"),
              digest = rows.column("digest"), segments = rows.column("segments");
    while (rows.step()) {
        out.push_back({rows.column_text(name), rows.column_text(file), rows.column_text(made_from),
                       rows.column_text(digest), rows.column_int(segments)});
    }
    return out;
}

void create_campaign_db(const fs::path& path, const CampaignConfig& config,
                        const std::vector<PlannedRun>& plan) {
    db::OutputDatabase output(path, false);
    auto& connection = output.connection();
    connection.prepare(db::sql("campaign/insert_campaign.sql"))
        .bind(":config", config.to_json().dump())
        .step();
    {
        auto insert = connection.prepare(db::sql("campaign/insert_run.sql"));
        for (std::size_t k = 0; k < plan.size(); ++k) {
            insert.reset();
            insert.bind(":id", static_cast<std::int64_t>(k + 1))
                .bind(":step", to_string(plan[k].step))
                .bind(":treatment", to_string(plan[k].treatment))
                .bind(":seed", static_cast<std::int64_t>(plan[k].seed))
                .bind(":file", plan[k].file)
                .bind(":generations", plan[k].generations)
                .step();
        }
    }  // the statement is finalized before the file is moved into place
    output.commit();
}

std::optional<RunFileState> read_run_file(const fs::path& path) {
    if (!fs::exists(path)) return std::nullopt;
    auto connection = db::open_database(path, db::OpenMode::read_only);
    const RunRecord run = load_run(connection);
    RunFileState state;
    state.generations_done = run.generations_done;
    state.finished = run.status == RunStatus::finished;
    state.best_reward = best_reward(connection).value_or(0.0);
    return state;
}

void update_run_row(db::Connection& connection, const CampaignRun& state,
                    const std::optional<std::string>& digest, double wall_time,
                    const std::optional<std::string>& error) {
    auto update = connection.prepare(db::sql("campaign/update_run.sql"));
    update.bind(":status", to_string(state.status))
        .bind(":generations_done", state.generations_done)
        .bind(":best_reward", state.best_reward)
        .bind(":digest", digest)
        .bind(":wall_time", wall_time)
        .bind(":error", error)
        .bind(":id", state.id);
    update.step();
}

void record_kb(db::Connection& connection, const std::string& name, const std::string& file,
               const std::string& made_from, const fs::path& path) {
    auto kb_connection = db::open_database(path, db::OpenMode::read_only);
    const auto stored = db::load_kb(kb_connection);
    auto upsert = connection.prepare(db::sql("campaign/upsert_kb.sql"));
    upsert.bind(":name", name)
        .bind(":file", file)
        .bind(":made_from", made_from)
        .bind(":segments", static_cast<std::int64_t>(stored.kb.size()))
        .bind(":digest", db::kb_digest(stored.kb, stored.randomized_seed));
    upsert.step();
}

}  // namespace stepstone::runs
