// stepstone simulate: one evaluation of a built-in controller, one CSV row per step

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>

#include "commands.hpp"
#include "core/error.hpp"
#include "core/text.hpp"
#include "sim/controllers.hpp"
#include "sim/episode.hpp"
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
    config.steps_per_start = options.steps;
    config.starts = options.starts;
    config.validate();
    return config;
}

// writes rows as the episode runs; doubles with 17 digits and floats with 9
// so the text round-trips and identical runs give identical files
class CsvRows {
public:
    explicit CsvRows(std::ostream& out) : out_(out) {
        out_ << "start,step,x,y,heading";
        for (const char* name : sim::channel_names()) out_ << ',' << name;
        out_ << ",carrying_after,balls\n";
    }
    void operator()(const sim::StepView& view) {
        char buffer[64];
        out_ << view.start << ',' << view.step;
        for (double v : {view.pose.x, view.pose.y, view.pose.heading}) {
            std::snprintf(buffer, sizeof buffer, ",%.17g", v);
            out_ << buffer;
        }
        for (int i = 0; i < sim::kInputs; ++i) write_float(view.inputs[i]);
        for (int i = 0; i < sim::kOutputs; ++i) write_float(view.outputs[i]);
        out_ << ',' << (view.carrying ? 1 : 0) << ',' << view.balls << '\n';
    }

private:
    void write_float(float v) {
        char buffer[32];
        std::snprintf(buffer, sizeof buffer, ",%.9g", static_cast<double>(v));
        out_ << buffer;
    }
    std::ostream& out_;
};

void run_simulate(const SimulateOptions& options) {
    const sim::TaskConfig config = task_config(options);
    const std::filesystem::path target(options.csv);
    if (std::filesystem::exists(target) && !options.force) {
        throw ConfigError(concat(options.csv, ": file exists (use --force to overwrite)"));
    }
    const auto task = sim::make_task(config);

    // write under a temporary name; rename only once the run is complete
    const std::filesystem::path temporary = target.string() + ".tmp";
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out) throw Error(concat(temporary.string(), ": cannot create file"));
    CsvRows rows(out);
    sim::EpisodeResult result;
    if (options.controller == "scripted") {
        sim::ScriptedController controller(config.kind);
        result = sim::run_episode(*task, controller, {}, rows);
    } else {
        sim::RandomController controller(options.seed);
        result = sim::run_episode(*task, controller, {}, rows);
    }
    out.close();
    if (!out) {
        std::filesystem::remove(temporary);
        throw Error(concat(temporary.string(), ": write failed"));
    }
    std::error_code error;
    std::filesystem::rename(temporary, target, error);
    if (error) {
        std::filesystem::remove(temporary);
        throw Error(concat(options.csv, ": cannot rename the finished file: ", error.message()));
    }

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
    cmd->add_flag("--force", options->force, "Overwrite an existing CSV");
    cmd->footer(example({"stepstone simulate --task source --controller scripted --csv source.csv",
                         "stepstone simulate --task target --controller random --seed 7 --steps 500 --starts 1 --csv r.csv"}));
    cmd->callback([options] { run_simulate(*options); });
}

const CommandRegistrar registrar(20, add_simulate_command);

}  // namespace

}  // namespace stepstone::app
