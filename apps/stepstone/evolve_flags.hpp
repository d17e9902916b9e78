#pragma once

// The flags of `stepstone evolve` and their translation to and from the
// engine's options. evolve_command_line is the parser's inverse: a campaign's
// child process is started with it, and tests/cli checks the round trip.

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "exp/campaign/campaign.hpp"
#include "exp/evolution.hpp"

namespace stepstone::app {

/// The flags of `stepstone evolve` as typed.
struct EvolveFlags {
    std::string config;
    std::string db;
    std::string seed;
    int generations = -1;
    unsigned threads = 0;
    std::string retain;
    std::string kb;
    std::string kb_name;
    std::string treatment;
    std::string seed_from;
    std::string seed_with;
    std::string seed_count;
    bool resume = false;
    bool allow_config_change = false;
    bool force = false;
    bool quiet = false;
    bool mpi = false;
};

/// Adds the flags of `stepstone evolve` to `cmd`, bound to `flags`.
void add_evolve_flags(CLI::App& cmd, EvolveFlags& flags);

/// The engine's options for `flags` (--mpi aside: it needs an MPI session).
/// Throws ConfigError naming the flag for a value the flags' checks let through.
exp::EvolveOptions evolve_options(const EvolveFlags& flags);

/// The arguments of `stepstone evolve` (after the program's name, from
/// "evolve" on) that `evolve_options` reads back as `options`. Options with no
/// flag (mpi, stop_on_signals) must be at their defaults; throws ConfigError
/// otherwise.
std::vector<std::string> evolve_command_line(const exp::EvolveOptions& options);

/// How a campaign of this CLI runs each run: this very binary with
/// `evolve_command_line`.
exp::RunCommand evolve_run_command();

}  // namespace stepstone::app
