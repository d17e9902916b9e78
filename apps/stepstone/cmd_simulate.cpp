// stepstone simulate: one evaluation of a built-in controller, one CSV row per step

#include <iostream>
#include <memory>
#include <string>

#include "commands.hpp"
#include "core/error.hpp"
#include "core/output_file.hpp"
#include "core/text.hpp"
#include "sim/controllers.hpp"
#include "sim/episode.hpp"
#include "sim/step_csv.hpp"
#include "sim/task.hpp"

namespace stepstone::app {

namespace {

struct SimulateOptions {
    std::string task = "source";
    std::string controller = "scripted";
    std::uint64_t seed = 1;
    std::string csv;
    int steps = 4000;
    int starts = 3;
    std::string arena;
    std::string math = "portable";
    bool force = false;
};

sim::TaskConfig task_config(const SimulateOptions& options) {
    sim::TaskConfig config;
    config.kind = sim::parse_task_kind(options.task, "--task");
    if (options.controller != "scripted" && options.controller != "random") {
        throw ConfigError(concat("--controller must be scripted or random, got '", options.controller, "'"));
    }
    if (options.steps < 1 || options.steps > 10'000'000) {
        throw ConfigError(concat("--steps must be in [1, 10000000], got ", options.steps));
    }
    if (options.starts < 1 || options.starts > 3) {
        throw ConfigError(concat("--starts must be in [1, 3], got ", options.starts));
    }
    const std::optional<Math> math = parse_math(options.math);
    if (!math) throw ConfigError(concat("--math must be libm or portable, got '", options.math, "'"));
    config.steps_per_start = options.steps;
    config.starts = options.starts;
    config.math = *math;
    if (!options.arena.empty()) {
        config.arena = std::make_shared<const sim::ArenaSpec>(sim::ArenaSpec::load(options.arena));
        if (options.controller == "scripted" && *config.arena != sim::paper_arena()) {
            throw ConfigError(
                concat("--controller scripted follows waypoints of the paper's arena only; use "
                       "--controller random with --arena ",
                       options.arena));
        }
    }
    config.validate();
    return config;
}

void run_simulate(const SimulateOptions& options) {
    const sim::TaskConfig config = task_config(options);
    const auto task = sim::make_task(config);

    // rows go to a temporary file, renamed only once the run is complete
    OutputFile output(options.csv, options.force);
    sim::StepCsvWriter rows(output.stream());
    sim::EpisodeResult result;
    if (options.controller == "scripted") {
        sim::ScriptedController controller(config.kind);
        result = sim::run_episode(*task, controller, {}, rows);
    } else {
        sim::RandomController controller(options.seed);
        result = sim::run_episode(*task, controller, {}, rows);
    }
    output.commit();

    std::cout << "reward " << result.reward << " (" << result.balls << " balls, " << result.steps_run << " steps"
              << (result.stopped_early ? ", stopped early by the stand-still rule" : "") << ", "
              << result.nan_outputs << " NaN outputs)\n";
}

void add_simulate_command(CLI::App& app) {
    auto options = std::make_shared<SimulateOptions>();
    auto* cmd = app.add_subcommand("simulate", "Run one evaluation of a built-in controller and write every step as CSV");
    cmd->add_option("--task", options->task, "source or target")->capture_default_str();
    cmd->add_option("--controller", options->controller,
                    "scripted (waypoint follower using the true pose) or random (uniform outputs)")
        ->capture_default_str();
    cmd->add_option("--seed", options->seed, "Seed of the random controller")->capture_default_str();
    cmd->add_option("--csv", options->csv, "Output CSV: one row per step")->required();
    cmd->add_option("--steps", options->steps, "Steps per start")->capture_default_str();
    cmd->add_option("--starts", options->starts, "Number of starts, 1 to 3")->capture_default_str();
    cmd->add_option("--arena", options->arena,
                    "Arena file (JSON, docs/simulator.md; default: the paper's arena)");
    cmd->add_option(
           "--math", options->math,
           "Sine and cosine: portable (stepstone's own, the default: the same bits on every machine) or "
           "libm (the C library's, as runs made before 0.2.0 used; docs/architecture.md, Determinism)")
        ->capture_default_str();
    cmd->add_flag("--force", options->force, "Overwrite an existing CSV");
    cmd->footer(example(
        {"stepstone simulate --task source --controller scripted --csv source.csv",
         "stepstone simulate --task target --controller random --seed 7 --steps 500 --starts 1 --csv r.csv",
         "stepstone simulate --arena examples/arenas/two_rooms.json --controller random --csv a.csv"}));
    cmd->callback([options] { run_simulate(*options); });
}

const CommandRegistrar simulate_registrar(20, add_simulate_command);

}  // namespace

}  // namespace stepstone::app
