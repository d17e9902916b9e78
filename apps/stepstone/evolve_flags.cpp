#include "evolve_flags.hpp"

#include <charconv>
#include <filesystem>

#include "core/error.hpp"
#include "core/text.hpp"

namespace stepstone::app {

namespace {

// a seed as typed: digits only, within [0, 2^63 - 1] (no sign, no rounding, no wrap-around)
std::uint64_t parse_seed(const std::string& text) {
    std::uint64_t value = 0;
    const auto parsed = std::from_chars(text.data(), text.data() + text.size(), value);
    if (text.empty() || parsed.ec != std::errc() || parsed.ptr != text.data() + text.size() ||
        value > static_cast<std::uint64_t>(runs::kMaxSeed)) {
        throw ConfigError("--seed must be an integer from 0 to " + std::to_string(runs::kMaxSeed) + ", got " +
                          text);
    }
    return value;
}

// a count as typed: digits only, from 1 to 10^9
int parse_count(const std::string& text, const char* flag) {
    int value = 0;
    const auto parsed = std::from_chars(text.data(), text.data() + text.size(), value);
    if (parsed.ec != std::errc() || parsed.ptr != text.data() + text.size() || value < 1 ||
        value > 1000000000) {
        throw ConfigError(concat(flag, " must be an integer from 1 to 1000000000, got ", text));
    }
    return value;
}

const CLI::Validator kNotEmpty(
    [](std::string& value) { return value.empty() ? std::string("an empty value") : std::string(); }, "",
    "not empty");

}  // namespace

void add_evolve_flags(CLI::App& cmd, EvolveFlags& flags) {
    cmd.add_option("--config", flags.config,
                   "Run config (JSON): task, ea, dnn, kb, transfer, seed, retain (with --resume: default the "
                   "run's stored one)");
    cmd.add_option("--db", flags.db, "Run database to create (or to continue with --resume)")->required();
    cmd.add_option("--seed", flags.seed, "Run seed (default: the config's, else drawn and stored)")
        ->check(kNotEmpty);
    cmd.add_option("--generations", flags.generations,
                   "Epochs after the random generation 0 (overrides ea.generations)")
        ->check(kNotEmpty);
    cmd.add_option("--threads", flags.threads,
                   "Evaluation threads, 1 to 1024 (default: all cores); results do not depend on it")
        ->check(kNotEmpty)
        ->check(CLI::Range(1u, 1024u));
    cmd.add_option("--retain", flags.retain, "Genomes to store: front (first front + best, default) or all")
        ->check(CLI::IsMember({"front", "all"}));
    cmd.add_option("--kb", flags.kb, "Knowledge base file that shapes the reward (overrides transfer.kb)");
    cmd.add_option("--kb-name", flags.kb_name, "The KB to use in that file (default: its only one)");
    cmd.add_option(
        "--treatment", flags.treatment,
        "How the KB shapes the reward: none, sum, mo, sum-rand, mo-rand (overrides transfer.treatment)");
    cmd.add_option("--seed-from", flags.seed_from,
                   "A finished run file whose policies seed generation 0 (overrides transfer.seed.from)")
        ->check(kNotEmpty);
    cmd.add_option("--seed-with", flags.seed_with,
                   "Which of its policies: population (default: its last population), front (its first "
                   "front) or best (its best stored genomes) (overrides transfer.seed.with)")
        ->check(CLI::IsMember({"population", "front", "best"}));
    cmd.add_option("--seed-count", flags.seed_count,
                   "At most this many seeds, the best by task reward first (default: the population size; "
                   "overrides transfer.seed.count)")
        ->check(kNotEmpty);
    cmd.add_flag("--resume", flags.resume, "Continue the run in --db from its last committed generation");
    cmd.add_flag("--allow-config-change", flags.allow_config_change,
                 "With --resume: accept a config that differs");
    cmd.add_flag("--force", flags.force, "Replace an existing --db");
    cmd.add_flag("--quiet", flags.quiet, "No progress on stderr");
    cmd.add_flag("--mpi", flags.mpi,
                 "Under mpirun: each generation's evaluations spread over the ranks; rank 0 writes --db "
                 "(docs/scaling.md)");
}

exp::EvolveOptions evolve_options(const EvolveFlags& flags) {
    if (flags.generations < -1)
        throw ConfigError("--generations must be >= 0, got " + std::to_string(flags.generations));
    exp::EvolveOptions options;
    options.config_path = flags.config;
    options.db_path = flags.db;
    if (!flags.seed.empty()) options.seed = parse_seed(flags.seed);
    if (flags.generations >= 0) options.generations = flags.generations;
    if (flags.retain == "all") options.retain = runs::Retain::all;
    if (flags.retain == "front") options.retain = runs::Retain::front;
    if (!flags.kb.empty()) options.kb = flags.kb;
    if (!flags.kb_name.empty()) options.kb_name = flags.kb_name;
    if (!flags.treatment.empty())
        options.treatment = runs::parse_shaping_treatment(flags.treatment, "--treatment");
    if (!flags.seed_from.empty()) options.seed_from = flags.seed_from;
    if (!flags.seed_with.empty()) options.seed_with = runs::parse_seed_with(flags.seed_with, "--seed-with");
    if (!flags.seed_count.empty()) options.seed_count = parse_count(flags.seed_count, "--seed-count");
    options.threads = flags.threads;
    options.resume = flags.resume;
    options.allow_config_change = flags.allow_config_change;
    options.force = flags.force;
    options.progress = flags.quiet ? ProgressMode::quiet : ProgressMode::automatic;
    if (options.resume && options.force) throw ConfigError("--resume and --force cannot be used together");
    return options;
}

std::vector<std::string> evolve_command_line(const exp::EvolveOptions& options) {
    if (options.mpi || !options.stop_on_signals) {
        throw ConfigError("a run on MPI ranks or without its own signals has no evolve command line");
    }
    if (options.progress != ProgressMode::quiet && options.progress != ProgressMode::automatic) {
        throw ConfigError("evolve's command line shows progress automatically or not at all (--quiet)");
    }
    // --flag=value: a value that starts with a dash is still read as the value
    std::vector<std::string> args{"evolve"};
    const auto add = [&](const char* flag, const std::string& value) {
        args.push_back(concat(flag, '=', value));
    };
    add("--db", options.db_path.string());
    if (!options.config_path.empty()) add("--config", options.config_path.string());
    if (options.seed) add("--seed", std::to_string(*options.seed));
    if (options.generations) add("--generations", std::to_string(*options.generations));
    if (options.threads > 0) add("--threads", std::to_string(options.threads));
    if (options.retain) add("--retain", *options.retain == runs::Retain::all ? "all" : "front");
    if (options.kb) add("--kb", options.kb->string());
    if (options.kb_name) add("--kb-name", *options.kb_name);
    if (options.treatment) add("--treatment", std::string(runs::to_string(*options.treatment)));
    if (options.seed_from) add("--seed-from", options.seed_from->string());
    if (options.seed_with) add("--seed-with", std::string(runs::to_string(*options.seed_with)));
    if (options.seed_count) add("--seed-count", std::to_string(*options.seed_count));
    if (options.resume) args.emplace_back("--resume");
    if (options.allow_config_change) args.emplace_back("--allow-config-change");
    if (options.force) args.emplace_back("--force");
    if (options.progress == ProgressMode::quiet) args.emplace_back("--quiet");
    return args;
}

exp::RunCommand evolve_run_command() {
    const std::string program = std::filesystem::read_symlink("/proc/self/exe").string();
    return [program](const exp::EvolveOptions& options) {
        std::vector<std::string> argv{program};
        const auto args = evolve_command_line(options);
        argv.insert(argv.end(), args.begin(), args.end());
        return argv;
    };
}

}  // namespace stepstone::app
