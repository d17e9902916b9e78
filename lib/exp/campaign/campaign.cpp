#include "exp/campaign/campaign.hpp"

#include <optional>

#include "core/error.hpp"
#include "core/text.hpp"
#include "db/database.hpp"
#include "exp/campaign/campaign_mpi.hpp"
#include "exp/campaign/campaign_runner.hpp"
#include "exp/parallel/writer_lock.hpp"

namespace stepstone::exp {

namespace fs = std::filesystem;

namespace {

ConfigError already_a_campaign(const fs::path& dir) {
    return ConfigError(concat(dir.string(), " already holds a campaign (", runs::kCampaignFile, "); add ",
                              option_name("resume"), " to continue it"));
}

// refuses a --dir that is not a folder, a new campaign over an existing one
// and a resume of none
void check_campaign_dir(const CampaignOptions& options) {
    const fs::path campaign_path = options.dir / runs::kCampaignFile;
    const std::string dir_name = options.dir.string();
    if (fs::exists(options.dir) && !fs::is_directory(options.dir)) {
        throw ConfigError(concat(dir_name, ": exists and is not a directory (", option_name("dir"),
                                 " names the campaign's folder)"));
    }
    if (!options.resume && fs::exists(campaign_path)) throw already_a_campaign(options.dir);
    if (options.resume && !fs::exists(campaign_path)) {
        throw ConfigError(concat(dir_name, " holds no ", runs::kCampaignFile, "; run without ",
                                 option_name("resume"), " to start it"));
    }
}

// campaign.db for a new campaign; for a resumed one, the stored config must be the given one
// A step whose config names no math keeps the math the campaign was made with: its stored
// step config holds "math" when portable and nothing when libm (every campaign made before
// portable became the default).
void inherit_math(runs::RunStep& step, const nlohmann::json& stored_step) {
    if (step.config.math_given || !stored_step.is_object() || !stored_step.contains("config")) return;
    if (const auto math = runs::stored_math(stored_step["config"])) step.config.set_math(*math);
}

runs::CampaignIndex open_campaign(const CampaignOptions& options, runs::CampaignConfig& config) {
    const fs::path campaign_path = options.dir / runs::kCampaignFile;
    if (!options.resume) {
        if (fs::exists(campaign_path)) throw already_a_campaign(options.dir);  // checked again under the lock
        create_campaign_db(campaign_path, config, plan_runs(config));
        return runs::load_campaign(options.dir);
    }
    runs::recover_campaign_db(campaign_path);
    auto index = runs::load_campaign(options.dir);
    // campaigns made before kb.file was stored as given hold its absolute path: the same file
    auto stored = index.config;
    if (config.source && stored.contains("source")) inherit_math(*config.source, stored["source"]);
    if (stored.contains("target")) inherit_math(config.target, stored["target"]);
    if (stored.contains("kb") && stored["kb"].contains("file") && stored["kb"]["file"].is_string() &&
        fs::path(stored["kb"]["file"].get<std::string>()) == config.kb_file) {
        stored["kb"]["file"] = config.kb_file_given;
    }
    const std::string diff = first_difference(stored, config.to_json());
    if (!diff.empty()) {
        throw ConfigError(concat(options.dir.string(), ": the config differs from the campaign's at ", diff));
    }
    return index;
}

// the evolve config every run of a step starts from, under config/
void write_step_configs(const fs::path& dir, const runs::CampaignConfig& config) {
    fs::create_directories(dir / "config");
    if (config.source) write_step_config(dir / "config" / "source.json", *config.source);
    write_step_config(dir / "config" / "target.json", config.target);
}

}  // namespace

void throw_on_failures(const CampaignSummary& summary, const fs::path& dir, std::ostream& err) {
    if (summary.failures.empty()) return;
    for (const auto& failure : summary.failures) err << "campaign: failed: " << failure << "\n";
    throw Error(concat(summary.failures.size(), " run(s) failed (logs in ", (dir / "logs").string(),
                       "); fix the cause and resume the campaign"));
}

CampaignSummary run_campaign(const CampaignOptions& given) {
    const CampaignOptions& options = given;
    runs::CampaignConfig config = runs::CampaignConfig::load(options.config_path);
    check_campaign_dir(options);
    fs::create_directories(options.dir);
    const WriterLock lock(options.dir / runs::kCampaignFile);  // one campaign process per folder
    const runs::CampaignIndex index = open_campaign(options, config);
    write_step_configs(options.dir, config);

    db::Connection connection =
        db::open_database(options.dir / runs::kCampaignFile, db::OpenMode::read_write);
    std::vector<runs::CampaignRun> runs = index.runs;
    std::uint64_t total = 0;
    for (const auto& state : runs) total += static_cast<std::uint64_t>(state.run.generations + 1);
    Progress progress("generation", total, options.progress);
    CampaignSummary summary;
    summary.runs = runs.size();
    const double started = now_seconds();
    // Ctrl-C and SIGTERM: the runs end their generation, then the campaign stops (an MPI job's
    // executor watches for mpirun's signals itself)
    std::optional<InterruptGuard> interrupts;
    if (!options.mpi) interrupts.emplace();
    const auto executor = options.mpi ? make_mpi_executor(*options.mpi)
                                      : make_process_executor(options.run_command, options.jobs);
    Runner runner(options, connection, runs, progress, *executor);

    // source runs, the KB step once they all finished, then target runs
    std::vector<std::size_t> sources, targets;
    for (std::size_t k = 0; k < runs.size(); ++k)
        (runs[k].run.step == runs::CampaignStep::source ? sources : targets).push_back(k);
    summary.failures = runner.execute(sources, summary);
    if (summary.failures.empty() && !InterruptGuard::received()) {
        if (config.needs_kb()) make_campaign_kbs(options.dir, config, connection, runs);
        if (config.seeded())
            runner.set_seeding(campaign_seed_source(options.dir, config, runs), *config.seed);
        if (!InterruptGuard::received()) summary.failures = runner.execute(targets, summary);
    }
    for (const auto& state : runs) summary.finished += state.status == runs::RunStatus::finished ? 1 : 0;
    summary.wall_time = now_seconds() - started;
    progress.finish(concat("runs ", summary.finished, "/", summary.runs));
    if (InterruptGuard::received() && summary.finished < summary.runs) {
        db::finish_writing(connection);  // no -wal / -shm left beside campaign.db
        connection.close();
        throw Interrupted(
            concat("campaign stopped with ", summary.finished, " of ", summary.runs,
                   " runs finished; every run file keeps its committed generations; continue with ",
                   option_name("resume")));
    }
    return summary;
}

}  // namespace stepstone::exp
