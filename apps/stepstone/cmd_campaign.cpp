// stepstone campaign: the paper's protocol as one resumable job

#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>

#include "commands.hpp"
#include "core/error.hpp"
#include "core/text.hpp"
#include "evolve_flags.hpp"
#include "exp/campaign/campaign.hpp"
#include "exp/campaign/campaign_mpi.hpp"
#include "exp/parallel/mpi.hpp"

namespace stepstone::app {

namespace {

struct CampaignFlags {
    std::string config;
    std::string dir;
    unsigned jobs = 0;
    unsigned threads = 0;
    bool resume = false;
    bool dry_run = false;
    bool quiet = false;
    bool mpi = false;
};

void run_campaign_command(const CampaignFlags& flags) {
    if (flags.dry_run) {
        const auto config = runs::CampaignConfig::load(flags.config);
        exp::write_plan(std::cout, config, exp::estimate_cost(config, flags.dir), flags.jobs);
        return;
    }
    exp::CampaignOptions options;
    options.config_path = flags.config;
    options.run_command = evolve_run_command();
    options.dir = flags.dir;
    options.jobs = flags.jobs;
    options.threads = flags.threads;
    options.resume = flags.resume;
    options.progress = flags.quiet ? ProgressMode::quiet : ProgressMode::automatic;
    std::optional<mpi::Session> session;
    std::optional<exp::MpiLeader> leader;  // tells the other ranks to stop, whatever happens
    if (flags.mpi) {
        session.emplace();
        if (session->rank() != 0) {
            exp::serve_campaign(*session);
            return;
        }
        leader.emplace(*session);
        options.mpi = &*leader;
    }
    const auto summary = [&] {
        try {
            return exp::run_campaign(options);
        } catch (const Interrupted& e) {
            throw Interrupted(
                concat(e.what(), " (stepstone campaign ", flags.config, " --dir ", flags.dir, " --resume)"));
        }
    }();
    std::cout << "runs " << summary.runs << "\n"
              << "finished " << summary.finished << "\n"
              << "already_finished " << summary.skipped << "\n"
              << "failed " << summary.failures.size() << "\n";
    exp::throw_on_failures(summary, flags.dir, std::cerr);
}

void add_campaign_command(CLI::App& app) {
    auto flags = std::make_shared<CampaignFlags>();
    auto* cmd = app.add_subcommand(
        "campaign", "Run a campaign: source runs, their KB, its randomized twin, target runs = treatments x seeds");
    cmd->add_option("config", flags->config, "Campaign config (JSON): source, kb, randomize_seed, target")
        ->required();
    cmd->add_option("--dir", flags->dir, "Campaign directory (campaign.db, one file per run, KBs, logs)");
    cmd->add_option("--jobs", flags->jobs, "Runs at a time (default: every core)");
    cmd->add_option("--threads", flags->threads,
                    "Evaluation threads of each run (default: the cores shared out among the runs going at once)")
        ->check(CLI::Range(1u, 1024u));
    cmd->add_flag("--resume", flags->resume, "Continue the campaign in --dir: finished runs are kept, others resumed");
    cmd->add_flag("--dry-run", flags->dry_run, "Print the plan and its estimated cost; run nothing");
    cmd->add_flag("--quiet", flags->quiet, "No progress on stderr");
    cmd->add_flag(
        "--mpi", flags->mpi,
        "Under mpirun: rank 0 keeps campaign.db and hands whole runs to the other ranks (docs/scaling.md)");
    cmd->footer(example({"stepstone campaign examples/campaign_quick.json --dir camp --jobs 2",
                         "stepstone campaign examples/campaign_quick.json --dir camp --resume",
                         "stepstone campaign examples/campaign_paper.json --dry-run",
                         "mpirun -np 8 stepstone campaign examples/campaign_quick.json --dir camp --mpi",
                         "stepstone stats camp"}));
    cmd->callback([flags] {
        if (!flags->dry_run && flags->dir.empty()) throw ConfigError("--dir is required (except with --dry-run)");
        if (flags->dry_run && flags->resume) throw ConfigError("--dry-run and --resume cannot be used together");
        if (flags->mpi && flags->dry_run) throw ConfigError("--dry-run and --mpi cannot be used together");
        if (flags->mpi && flags->jobs > 0) {
            throw ConfigError(
                "--jobs does not apply with --mpi: each rank but rank 0 runs one run at a time");
        }
        run_campaign_command(*flags);
    });
}

const CommandRegistrar campaign_registrar(50, add_campaign_command);

}  // namespace

}  // namespace stepstone::app
