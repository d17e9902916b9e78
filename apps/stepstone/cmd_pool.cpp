// stepstone pool: the statistics of runs pooled from several campaigns' CSVs

#include <iostream>
#include <memory>

#include "commands.hpp"
#include "core/error.hpp"
#include "core/output_file.hpp"
#include "core/text.hpp"
#include "report/canvas.hpp"
#include "report/event_figures.hpp"
#include "runs/pooled_stats.hpp"

namespace stepstone::app {

namespace {

struct PoolFlags {
    std::vector<std::string> runs, events;
    double threshold = 0.5;
    std::string event = "pickup";
    std::string runs_csv, tests_csv, events_csv, logrank_csv, hazard_csv, kaplan_meier;
    bool force = false;
};

void add_pool_command(CLI::App& app) {
    auto flags = std::make_shared<PoolFlags>();
    auto* cmd = app.add_subcommand(
        "pool",
        "Pool the runs and events CSVs of several campaigns (stats --runs-csv/--events-csv) and "
        "recompute their tests: Mann-Whitney on best rewards, Kaplan-Meier, log-rank, Cox hazard ratios "
        "and RMST on milestones");
    cmd->add_option("--runs", flags->runs, "Runs CSVs (stats --runs-csv), one or more")->required();
    cmd->add_option("--events", flags->events, "Events CSVs (stats --events-csv) of the same runs")
        ->required();
    cmd->add_option("--threshold", flags->threshold, "Success: best-of-run reward >= this (default 0.5)");
    cmd->add_option("--event", flags->event,
                    "Milestone of the time-to-event table: press, pickup, release or ball (default pickup)");
    cmd->add_option("--runs-csv", flags->runs_csv, "Write the pooled runs (the --runs format)");
    cmd->add_option("--tests-csv", flags->tests_csv,
                    "Write the Mann-Whitney tests (stats --tests-csv's format)");
    cmd->add_option("--events-csv", flags->events_csv, "Write the pooled events (the --events format)");
    cmd->add_option("--logrank-csv", flags->logrank_csv,
                    "Write the log-rank tests (stats --logrank-csv's format)");
    cmd->add_option("--hazard-csv", flags->hazard_csv,
                    "Write the Cox hazard ratios and restricted mean times of every log-rank pair "
                    "(stats --hazard-csv's format)");
    cmd->add_option("--kaplan-meier", flags->kaplan_meier, "Draw the Kaplan-Meier curves (.png or .svg)");
    cmd->add_flag("--force", flags->force, "Replace existing output files");
    cmd->footer(example(
        {"stepstone pool --runs a/runs.csv b/runs.csv --events a/events.csv b/events.csv",
         "stepstone pool --runs r1.csv --runs r2.csv --events e1.csv --events e2.csv --event ball "
         "--logrank-csv logrank.csv --kaplan-meier km.png",
         "stepstone pool --runs a/runs.csv b/runs.csv --events a/events.csv b/events.csv --event release "
         "--hazard-csv hazard.csv"}));
    cmd->callback([flags] {
        const runs::Milestone event = runs::parse_milestone(flags->event, "--event");
        for (const auto* path : {&flags->runs_csv, &flags->tests_csv, &flags->events_csv, &flags->logrank_csv,
                                 &flags->hazard_csv, &flags->kaplan_meier}) {
            if (!path->empty()) check_output_target(*path, flags->force);
        }
        std::optional<report::Format> figure_format;
        if (!flags->kaplan_meier.empty()) figure_format = report::format_of(flags->kaplan_meier);
        const std::vector<std::filesystem::path> runs(flags->runs.begin(), flags->runs.end());
        const std::vector<std::filesystem::path> events(flags->events.begin(), flags->events.end());
        const auto stats = runs::pool_stats(runs, events, flags->threshold);
        runs::write_pooled_text(std::cout, stats, event);
        write_output(flags->runs_csv, flags->force,
                     [&](std::ostream& out) { runs::write_run_rows(out, stats.runs); });
        write_output(flags->tests_csv, flags->force,
                     [&](std::ostream& out) { runs::write_pair_tests_csv(out, stats.tests); });
        write_output(flags->events_csv, flags->force, [&](std::ostream& out) {
            runs::write_events_csv(out, stats.run_events, stats.generation);
        });
        write_output(flags->logrank_csv, flags->force,
                     [&](std::ostream& out) { runs::write_logrank_csv(out, stats.events); });
        write_output(flags->hazard_csv, flags->force,
                     [&](std::ostream& out) { runs::write_hazard_csv(out, stats.events); });
        if (figure_format) {
            report::Canvas canvas(report::kPanelFigureWidth, report::kPanelFigureHeight, *figure_format);
            report::draw_kaplan_meier(canvas, stats.events);
            canvas.save(flags->kaplan_meier, flags->force);
        }
    });
}

const CommandRegistrar pool_registrar(56, add_pool_command);

}  // namespace

}  // namespace stepstone::app
