// stepstone evolve: the paper's direct policy search into a run file

#include <charconv>
#include <iostream>
#include <memory>
#include <optional>

#include "commands.hpp"
#include "core/error.hpp"
#include "core/mpi.hpp"
#include "exp/evolution.hpp"
#include "exp/mpi_evolve.hpp"

namespace stepstone::app {

namespace {

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
    bool resume = false;
    bool allow_config_change = false;
    bool force = false;
    bool quiet = false;
    bool mpi = false;
};

// a seed as typed: digits only, within [0, 2^63 - 1] (no sign, no rounding, no wrap-around)
std::uint64_t parse_seed(const std::string& text) {
    std::uint64_t value = 0;
    const auto parsed = std::from_chars(text.data(), text.data() + text.size(), value);
    if (text.empty() || parsed.ec != std::errc() || parsed.ptr != text.data() + text.size() ||
        value > static_cast<std::uint64_t>(exp::kMaxSeed)) {
        throw ConfigError("--seed must be an integer from 0 to " + std::to_string(exp::kMaxSeed) + ", got " + text);
    }
    return value;
}

const CLI::Validator kNotEmpty([](std::string& value) { return value.empty() ? std::string("an empty value") : std::string(); },
                               "", "not empty");

void run_evolve_command(const EvolveFlags& flags) {
    exp::EvolveOptions options;
    options.config_path = flags.config;
    options.db_path = flags.db;
    if (!flags.seed.empty()) options.seed = parse_seed(flags.seed);
    if (flags.generations >= 0) options.generations = flags.generations;
    if (flags.retain == "all") options.retain = exp::Retain::all;
    if (flags.retain == "front") options.retain = exp::Retain::front;
    if (!flags.kb.empty()) options.kb = flags.kb;
    if (!flags.kb_name.empty()) options.kb_name = flags.kb_name;
    if (!flags.treatment.empty()) options.treatment = exp::parse_treatment(flags.treatment, "--treatment");
    options.threads = flags.threads;
    options.resume = flags.resume;
    options.allow_config_change = flags.allow_config_change;
    options.force = flags.force;
    options.progress = flags.quiet ? ProgressMode::quiet : ProgressMode::automatic;
    if (options.resume && options.force) throw ConfigError("--resume and --force cannot be used together");

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
    const auto summary = exp::run_evolve(options);
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
    cmd->add_option("--config", flags->config, "Run config (JSON): task, ea, dnn, kb, transfer, seed, retain (with --resume: default the run's stored one)");
    cmd->add_option("--db", flags->db, "Run database to create (or to continue with --resume)")->required();
    cmd->add_option("--seed", flags->seed, "Run seed (default: the config's, else drawn and stored)")->check(kNotEmpty);
    cmd->add_option("--generations", flags->generations, "Epochs after the random generation 0 (overrides ea.generations)")
        ->check(kNotEmpty);
    cmd->add_option("--threads", flags->threads,
                    "Evaluation threads, 1 to 1024 (default: all cores); results do not depend on it")
        ->check(kNotEmpty)
        ->check(CLI::Range(1u, 1024u));
    cmd->add_option("--retain", flags->retain, "Genomes to store: front (first front + best, default) or all")
        ->check(CLI::IsMember({"front", "all"}));
    cmd->add_option("--kb", flags->kb, "Knowledge base file that shapes the reward (overrides transfer.kb)");
    cmd->add_option("--kb-name", flags->kb_name, "The KB to use in that file (default: its only one)");
    cmd->add_option("--treatment", flags->treatment,
                    "How the KB shapes the reward: none, sum, mo, sum-rand, mo-rand (overrides transfer.treatment)");
    cmd->add_flag("--resume", flags->resume, "Continue the run in --db from its last committed generation");
    cmd->add_flag("--allow-config-change", flags->allow_config_change, "With --resume: accept a config that differs");
    cmd->add_flag("--force", flags->force, "Replace an existing --db");
    cmd->add_flag("--quiet", flags->quiet, "No progress on stderr");
    cmd->add_flag("--mpi", flags->mpi,
                  "Under mpirun: each generation's evaluations spread over the ranks; rank 0 writes --db "
                  "(docs/scaling.md)");
    cmd->footer(example({"stepstone evolve --config examples/source_quick.json --db run.db --seed 1",
                         "stepstone evolve --db run.db --resume --generations 40",
                         "stepstone evolve --config examples/target_quick.json --db sum.db --kb kb.db --treatment sum"}));
    cmd->callback([flags] {
        if (flags->generations < -1) {
            throw ConfigError("--generations must be >= 0, got " + std::to_string(flags->generations));
        }
        run_evolve_command(*flags);
    });
}

const CommandRegistrar evolve_registrar(10, add_evolve_command);

}  // namespace

}  // namespace stepstone::app
