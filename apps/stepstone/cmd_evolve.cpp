// stepstone evolve: the paper's direct policy search into a run file

#include <iostream>
#include <memory>
#include <optional>

#include "commands.hpp"
#include "core/error.hpp"
#include "core/text.hpp"
#include "evolve_flags.hpp"
#include "exp/evolution.hpp"
#include "exp/mpi_evolve.hpp"
#include "exp/parallel/mpi.hpp"

namespace stepstone::app {

namespace {

void run_evolve_command(const EvolveFlags& flags) {
    exp::EvolveOptions options = evolve_options(flags);

    std::optional<mpi::Session> session;
    std::optional<exp::MpiLeader> leader;  // tells the other ranks to stop, whatever happens
    if (flags.mpi) {
        session.emplace();
        // a rank is a core (Slurm's --ntasks); more threads each with --threads
        if (flags.threads == 0) options.threads = 1;
        if (session->rank() != 0) {
            exp::serve_evolve(*session, options.threads);
            return;
        }
        leader.emplace(*session);
        options.mpi = &*leader;
    }
    if (flags.db.empty()) throw ConfigError("--db is empty: name the run file to write");
    const auto summary = [&] {
        try {
            return exp::run_evolve(options);
        } catch (const Interrupted& e) {
            // the whole command that resumes, as the README promises
            throw Interrupted(concat(e.what(), " (stepstone evolve --db ", flags.db, " --resume)"));
        }
    }();
    if (summary.was_finished) {
        std::cerr << flags.db << ": already at generation " << summary.generations_done << ", nothing to do\n";
    }
    std::cout << "seed " << summary.seed << "\n"
              << "generations " << summary.generations_done << "\n"
              << "evaluations " << summary.evaluations << "\n"
              << "best_reward " << summary.best_reward << "\n";
}

void add_evolve_command(CLI::App& app) {
    auto flags = std::make_shared<EvolveFlags>();
    auto* cmd = app.add_subcommand("evolve", "Evolve neural-network policies with NSGA-II into a run database");
    add_evolve_flags(*cmd, *flags);
    cmd->footer(example(
        {"stepstone evolve --config examples/source_quick.json --db run.db --seed 1",
         "stepstone evolve --db run.db --resume --generations 40",
         "stepstone evolve --config examples/target_quick.json --db sum.db --kb kb.db --treatment sum",
         "stepstone evolve --config examples/target_quick.json --db seeded.db --seed-from source.db "
         "--seed-with best --seed-count 16"}));
    cmd->callback([flags] { run_evolve_command(*flags); });
}

const CommandRegistrar evolve_registrar(10, add_evolve_command);

}  // namespace

}  // namespace stepstone::app
