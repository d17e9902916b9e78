// stepstone replay: re-simulate a stored genome exactly

#include <cmath>
#include <iostream>
#include <memory>

#include "commands.hpp"
#include "core/error.hpp"
#include "core/output_file.hpp"
#include "core/text.hpp"
#include "exp/replay.hpp"
#include "sim/step_csv.hpp"

namespace stepstone::app {

namespace {

struct ReplayFlags {
    std::string db;
    std::string individual = "best";
    std::string csv;
    bool force = false;
};

void run_replay(const ReplayFlags& flags) {
    exp::Replay replayed;
    if (flags.csv.empty()) {
        replayed = exp::replay(flags.db, flags.individual);
    } else {
        // rows go to a temporary file, renamed once the replay is complete
        OutputFile output(flags.csv, flags.force);
        replayed = exp::replay(flags.db, flags.individual, sim::StepCsvWriter(output.stream()));
        output.commit();
    }
    std::cout << "individual " << replayed.individual_id << " (generation " << replayed.generation << ")\n"
              << "reward " << replayed.result.reward << "\n"
              << "balls " << replayed.result.balls << "\n"
              << "steps " << replayed.result.steps_run << "\n"
              << "stored_reward " << replayed.stored_reward << "\n";
    if (replayed.result.reward != replayed.stored_reward) {
        throw DataError(concat(flags.db, ": individual ", replayed.individual_id, " replays to reward ",
                               replayed.result.reward, ", the run stored ", replayed.stored_reward));
    }
}

void add_replay_command(CLI::App& app) {
    auto flags = std::make_shared<ReplayFlags>();
    auto* cmd = app.add_subcommand("replay", "Re-simulate a stored genome and check its reward");
    cmd->add_option("db", flags->db, "Run database (opened read-only)")->required();
    cmd->add_option("--individual", flags->individual, "'best' (default) or an individual id");
    cmd->add_option("--csv", flags->csv, "Also write every step as CSV (columns as `stepstone simulate`)");
    cmd->add_flag("--force", flags->force, "Overwrite an existing --csv file");
    cmd->footer(example({"stepstone replay run.db --individual best", "stepstone replay run.db --individual 412 --csv best.csv"}));
    cmd->callback([flags] { run_replay(*flags); });
}

const CommandRegistrar registrar(30, add_replay_command);

}  // namespace

}  // namespace stepstone::app
