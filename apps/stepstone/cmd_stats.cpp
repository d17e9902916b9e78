// stepstone stats: success curves and Mann-Whitney tests of a campaign

#include <iostream>
#include <memory>

#include "commands.hpp"
#include "core/error.hpp"
#include "core/output_file.hpp"
#include "core/text.hpp"
#include "runs/campaign_stats.hpp"

namespace stepstone::app {

namespace {

struct StatsFlags {
    std::string dir;
    int generation = -1;
    double threshold = 0.5;
    std::string csv;
    std::string runs_csv;
    std::string tests_csv;
    std::string events_csv;
    std::string logrank_csv;
    std::string hazard_csv;
    std::string event = "pickup";
    bool force = false;
    bool available = false;
    int signal_window = 10;
};

void add_stats_command(CLI::App& app) {
    auto flags = std::make_shared<StatsFlags>();
    auto* cmd =
        app.add_subcommand("stats",
                           "Success counts, best rewards, Mann-Whitney U tests and times to each "
                           "milestone (Kaplan-Meier, log-rank, Cox hazard ratio, RMST) of a campaign");
    cmd->add_option("dir", flags->dir, "Campaign directory (holds campaign.db)")->required();
    cmd->add_option("--generation", flags->generation, "Generation to compare at (default: the target budget)");
    cmd->add_option("--threshold", flags->threshold, "Success: best-of-run reward >= this (default 0.5)");
    cmd->add_option("--csv", flags->csv, "Write successful runs per treatment per generation (Fig. 6's data)");
    cmd->add_option("--signal-window", flags->signal_window,
                    "Generations up to --generation whose policies' r_max is averaged (default 10)");
    cmd->add_option(
        "--runs-csv", flags->runs_csv,
        "Write one row per run: treatment,seed,generation,best_reward,success,policies,ball_policies,"
        "mean_r_max");
    cmd->add_option("--tests-csv", flags->tests_csv,
                    "Write one row per pair: treatment_a,treatment_b,n_a,n_b,u,p,p_holm,a12");
    cmd->add_option(
        "--events-csv", flags->events_csv,
        "Write every run's first generation of each milestone: treatment,seed,event,generation,observed");
    cmd->add_option(
        "--logrank-csv", flags->logrank_csv,
        "Write the log-rank tests of every milestone: treatment_a,treatment_b,event,n_a,n_b,events_a,"
        "events_b,chi2,p,p_holm");
    cmd->add_option(
        "--hazard-csv", flags->hazard_csv,
        "Write the Cox hazard ratio (Efron ties, 95% Wald CI) and restricted mean times of every log-rank "
        "pair: treatment_a,treatment_b,event,n_a,n_b,events_a,events_b,hazard_ratio,ci_low,ci_high,log_hr,"
        "se,p_wald,score_chi2,p_score,ties,rmst_a,rmst_b,rmst_difference,horizon,note (docs/statistics.md)");
    auto* event_option = cmd->add_option(
        "--event", flags->event,
        "Milestone of the time-to-event table: press, pickup, release or ball (default pickup)");
    cmd->add_flag("--force", flags->force, "Replace existing CSV files");
    cmd->add_flag(
        "--available", flags->available,
        "A campaign still running: compare the runs that have reached the generation, list the others");
    cmd->footer(
        example({"stepstone stats camp", "stepstone stats camp --generation 10 --threshold 0.25",
                 "stepstone stats camp --available --generation 300",
                 "stepstone stats camp --runs-csv runs.csv --tests-csv tests.csv",
                 "stepstone stats camp --event ball --events-csv events.csv --logrank-csv logrank.csv",
                 "stepstone stats camp --event release --hazard-csv hazard.csv"}));
    cmd->callback([flags, event_option] {
        if (!(flags->threshold >= 0.0 && flags->threshold <= 1.0)) {
            throw ConfigError(concat("--threshold must be within [0, 1], got ", flags->threshold));
        }
        const runs::Milestone event = runs::parse_milestone(flags->event, "--event");
        // every output is checked before anything is computed or printed
        for (const auto* path : {&flags->csv, &flags->runs_csv, &flags->tests_csv, &flags->events_csv,
                                 &flags->logrank_csv, &flags->hazard_csv}) {
            if (!path->empty()) check_output_target(*path, flags->force);
        }
        std::optional<int> generation;
        if (flags->generation != -1) generation = flags->generation;
        const auto stats = runs::campaign_stats(flags->dir, generation, flags->threshold, flags->available,
                                                flags->signal_window);
        // time-to-event outputs asked of runs without milestones: refused before anything is written
        const bool events_asked = !flags->events_csv.empty() || !flags->logrank_csv.empty() ||
                                  !flags->hazard_csv.empty() || event_option->count() > 0;
        if (events_asked) runs::require_events(stats);
        runs::write_text(std::cout, stats, event);
        write_output(flags->csv, flags->force,
                     [&](std::ostream& out) { runs::write_success_csv(out, stats); });
        write_output(flags->runs_csv, flags->force,
                     [&](std::ostream& out) { runs::write_runs_csv(out, stats); });
        write_output(flags->tests_csv, flags->force,
                     [&](std::ostream& out) { runs::write_tests_csv(out, stats); });
        write_output(flags->events_csv, flags->force,
                     [&](std::ostream& out) { runs::write_events_csv(out, stats); });
        write_output(flags->logrank_csv, flags->force,
                     [&](std::ostream& out) { runs::write_logrank_csv(out, stats); });
        write_output(flags->hazard_csv, flags->force,
                     [&](std::ostream& out) { runs::write_hazard_csv(out, stats); });
    });
}

const CommandRegistrar stats_registrar(55, add_stats_command);

}  // namespace

}  // namespace stepstone::app
