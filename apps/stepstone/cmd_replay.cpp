// stepstone replay: re-simulate a stored genome exactly

#include <cmath>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <vector>

#include "commands.hpp"
#include "core/error.hpp"
#include "core/math_fingerprint.hpp"
#include "core/output_file.hpp"
#include "core/text.hpp"
#include "db/database.hpp"
#include "db/inspect.hpp"
#include "runs/replay.hpp"
#include "sim/sensors.hpp"
#include "sim/step_csv.hpp"

namespace stepstone::app {

namespace {

struct ReplayFlags {
    std::string db;
    std::string individual = "best";
    std::string csv;
    std::string behaviour_json;
    bool force = false;
};

// {"behaviour": rows of the first start's channels, ...}: the body of the
// service's /shape, and the file examples/python/kb_client.py reads
void write_behaviour_json(const ReplayFlags& flags) {
    if (flags.behaviour_json.empty()) return;
    runs::Replay facts;
    const std::vector<float> values = runs::replay_behaviour(flags.db, flags.individual, &facts);
    nlohmann::json rows = nlohmann::json::array();
    for (std::size_t at = 0; at + std::size_t{sim::kChannels} <= values.size();
         at += std::size_t{sim::kChannels}) {
        rows.push_back(std::vector<float>(values.begin() + static_cast<std::ptrdiff_t>(at),
                                          values.begin() + static_cast<std::ptrdiff_t>(at + sim::kChannels)));
    }
    const nlohmann::json document{{"behaviour", rows},
                                  {"individual", facts.individual_id},
                                  {"generation", facts.generation},
                                  {"start", 1}};
    write_output(flags.behaviour_json, flags.force,
                 [&](std::ostream& out) { out << document.dump() << "\n"; });
}

// why a replay may differ: the run came from a machine whose math library rounds
// otherwise (docs/architecture.md, Determinism); "" when it did not, or the file predates the key
std::string math_note(const std::string& db_path) {
    auto connection = db::open_database(db_path, db::OpenMode::read_only, /*allow_older=*/true);
    const std::string stored = db::meta_value(connection, kMathFingerprintKey);
    if (stored.empty() || stored == math_fingerprint()) return "";
    return concat(" (the run was made on a machine whose math library rounds differently: math fingerprint ",
                  stored, ", this machine's ", math_fingerprint(), ")");
}

void run_replay(const ReplayFlags& flags) {
    if (!flags.csv.empty()) check_output_target(flags.csv, flags.force);
    if (!flags.behaviour_json.empty()) check_output_target(flags.behaviour_json, flags.force);
    runs::Replay replayed;
    if (flags.csv.empty()) {
        replayed = runs::replay(flags.db, flags.individual);
    } else {
        // rows go to a temporary file, renamed once the replay is complete
        OutputFile output(flags.csv, flags.force);
        replayed = runs::replay(flags.db, flags.individual, sim::StepCsvWriter(output.stream()));
        output.commit();
    }
    std::cout << "individual " << replayed.individual_id << " (generation " << replayed.generation << ")\n"
              << "reward " << replayed.result.reward << "\n"
              << "balls " << replayed.result.balls << "\n"
              << "steps " << replayed.result.steps_run << "\n"
              << "stored_reward " << replayed.stored_reward << "\n";
    if (replayed.result.reward != replayed.stored_reward) {
        throw DataError(concat(flags.db, ": individual ", replayed.individual_id, " replays to reward ",
                               replayed.result.reward, ", the run stored ", replayed.stored_reward,
                               math_note(flags.db)));
    }
    write_behaviour_json(flags);
}

void add_replay_command(CLI::App& app) {
    auto flags = std::make_shared<ReplayFlags>();
    auto* cmd = app.add_subcommand("replay", "Re-simulate a stored genome and check its reward");
    cmd->add_option("db", flags->db, "Run database (opened read-only)")->required();
    cmd->add_option("--individual", flags->individual, "'best' (default) or an individual id")
        ->check(individual_check());
    cmd->add_option("--csv", flags->csv, "Also write every step as CSV (columns as `stepstone simulate`)");
    cmd->add_option("--behaviour-json", flags->behaviour_json,
                    "Also write the first start's behaviour matrix as {\"behaviour\": [[15 channels], ...]} "
                    "(the body of the service's /shape)");
    cmd->add_flag("--force", flags->force, "Overwrite an existing --csv or --behaviour-json file");
    cmd->footer(example({"stepstone replay run.db --individual best",
                         "stepstone replay run.db --individual 412 --csv best.csv",
                         "stepstone replay run.db --behaviour-json behaviour.json"}));
    cmd->callback([flags] { run_replay(*flags); });
}

const CommandRegistrar replay_registrar(30, add_replay_command);

}  // namespace

}  // namespace stepstone::app
