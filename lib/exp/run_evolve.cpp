// run_evolve: a run file's life, from its config (or its stored state) to its
// last generation, around the Evolution of exp/evolution.cpp
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "core/error.hpp"
#include "core/math_fingerprint.hpp"
#include "core/rng.hpp"
#include "core/text.hpp"
#include "core/version.hpp"
#include "db/database.hpp"
#include "db/digest.hpp"
#include "db/inspect.hpp"
#include "db/kb_store.hpp"
#include "exp/evolution.hpp"
#include "exp/mpi_evolve.hpp"
#include "exp/parallel/writer_lock.hpp"
#include "exp/seeding.hpp"

namespace stepstone::exp {

namespace {

// the config as compared on resume: the KB file and the seed source may move, their digests may not
nlohmann::json comparable(nlohmann::json config) {
    if (config.contains("transfer")) {
        config["transfer"].erase("kb");
        if (config["transfer"].contains("seed")) config["transfer"]["seed"].erase("from");
    }
    return config;
}

// Applies the command line's seed flags: --seed-from gives (or replaces) the
// seed source; --seed-with and --seed-count change a seed that the config, the
// stored run or --seed-from gives.
void apply_seed_options(runs::EvolveConfig& config, const EvolveOptions& options) {
    if (options.seed_count && *options.seed_count <= 0) {
        throw ConfigError(concat(option_name("seed_count"), " must be >= 1, got ", *options.seed_count));
    }
    if (options.seed_from) {
        if (!config.transfer) config.transfer = runs::TransferConfig{};
        auto& seed = config.transfer->seed;
        if (!seed) {
            seed = runs::SeedConfig{};
            seed->count = config.ea.population_size;
        }
        seed->from = *options.seed_from;
    }
    if (!options.seed_with && !options.seed_count) return;
    if (!config.seeding()) {
        throw ConfigError(concat(option_name(options.seed_with ? "seed_with" : "seed_count"),
                                 " needs a seed source (", option_name("seed_from"),
                                 " or transfer.seed.from)"));
    }
    if (options.seed_with) config.transfer->seed->with = *options.seed_with;
    if (options.seed_count) config.transfer->seed->count = *options.seed_count;
}

// Applies the command line's transfer flags; on resume, a run created with a
// transfer block keeps it when neither the config nor the flags name one.
void apply_transfer_options(runs::EvolveConfig& config, const EvolveOptions& options,
                            const runs::RunRecord* stored) {
    if (options.treatment || options.kb || options.kb_name) {
        if (!config.transfer) config.transfer = runs::TransferConfig{};
        if (options.treatment) config.transfer->treatment = *options.treatment;
        if (options.kb) config.transfer->kb = *options.kb;
        if (options.kb_name) config.transfer->kb_name = *options.kb_name;
    }
    if (!config.transfer && stored && stored->config.contains("transfer")) {
        config.transfer = runs::EvolveConfig::from_json(stored->config, "the run's stored config", {},
                                                        runs::ConfigOrigin::stored)
                              .transfer;
    }
    // after the stored block: a resume may move the seed source with --seed-from alone
    apply_seed_options(config, options);
    if (!config.transfer) return;
    auto& transfer = *config.transfer;
    if (transfer.treatment == runs::Treatment::none && transfer.kb.empty() && !transfer.seed) {
        config.transfer.reset();
        return;
    }
    if (transfer.treatment == runs::Treatment::none && transfer.kb.empty()) return;  // seeded, not shaped
    if (transfer.kb.empty()) {
        throw ConfigError(concat("treatment ", to_string(transfer.treatment), " needs a knowledge base (",
                                 option_name("kb"), " or transfer.kb)"));
    }
}

}  // namespace

kb::KnowledgeBase load_shaping_kb(runs::EvolveConfig& config) {
    auto& transfer = *config.transfer;
    const std::string file = transfer.kb.string();
    db::StoredKb stored = [&] {
        db::Connection connection = db::open_database(transfer.kb, db::OpenMode::read_only);
        return db::load_kb(connection, transfer.kb_name);
    }();
    const auto& params = stored.kb.params();
    if (params.channels != static_cast<std::size_t>(sim::kChannels)) {
        throw ConfigError(concat(file, ": the knowledge base has ", params.channels,
                                 " channels per step, the robot's behaviour has ", sim::kChannels));
    }
    if (params.segment_width > static_cast<std::size_t>(config.task.steps_per_start)) {
        throw ConfigError(concat(file, ": the knowledge base's segments are ", params.segment_width,
                                 " steps wide, longer than an episode start (", config.task.steps_per_start,
                                 " steps)"));
    }
    const bool randomized = stored.randomized_seed.has_value();
    if (needs_randomized_kb(transfer.treatment) && !randomized) {
        throw ConfigError(
            concat(file, ": treatment ", to_string(transfer.treatment),
                   " needs a randomized knowledge base (make one with stepstone kb randomize)"));
    }
    if (!needs_randomized_kb(transfer.treatment) && needs_kb(transfer.treatment) && randomized) {
        throw ConfigError(concat(file, ": the knowledge base is randomized; use treatment ",
                                 transfer.treatment == runs::Treatment::sum ? "sum-rand" : "mo-rand",
                                 " with it"));
    }
    const std::string digest = db::kb_digest(stored.kb, stored.randomized_seed);
    if (!transfer.kb_digest.empty() && transfer.kb_digest != digest) {
        throw ConfigError(concat(file, ": the knowledge base differs from the one the run was started with"));
    }
    transfer.kb_digest = digest;
    transfer.kb_name = stored.name;
    transfer.kb = std::filesystem::absolute(transfer.kb).lexically_normal();
    return std::move(stored.kb);
}

namespace {

kb::KbParams kb_params(const runs::KbConfig& config) {
    kb::KbParams params;
    params.segment_width = static_cast<std::size_t>(config.segment_width);
    params.channels = static_cast<std::size_t>(sim::kChannels);
    params.delta = config.delta;
    params.match = db::parse_match(config.match, "kb.match");
    params.counting = kb::parse_counting(config.counting, "kb.counting");
    params.validate();
    return params;
}

}  // namespace

namespace {

// the run file's preconditions, checked before anything is read
void check_run_file(const EvolveOptions& options) {
    const std::string name = options.db_path.string();
    if (options.config_path.empty() && !options.resume) {
        throw ConfigError(concat(option_name("config_path"), " is required (except with ",
                                 option_name("resume"), ", which reads the run's stored config)"));
    }
    if (!options.resume && !options.force && std::filesystem::exists(options.db_path)) {
        throw ConfigError(concat(name, ": already exists; continue it with ", option_name("resume"),
                                 " (or replace it with ", option_name("force"), ")"));
    }
    if (!options.resume) db::check_output_path(options.db_path, options.force);
    if (options.resume && !std::filesystem::exists(options.db_path)) {
        throw DatabaseError(
            concat(name, ": no such file (start the run without ", option_name("resume"), ")"));
    }
}

// What a run starts from, loaded and checked before a file is written: the
// effective config, the stored run when resumed (its file opened for writing at
// once, so that the WAL of a killed run is recovered) and the shaping KB.
struct RunStart {
    std::optional<db::Connection> resumed;
    std::optional<runs::RunRecord> stored;
    runs::EvolveConfig config;
    std::optional<kb::KnowledgeBase> shaping;
    std::optional<Seeds> seeds;  ///< generation 0's seeds, when it is still to run
};

RunStart load_run_start(const EvolveOptions& options) {
    RunStart start;
    const std::string name = options.db_path.string();
    if (options.resume) {
        start.resumed = db::open_database(options.db_path, db::OpenMode::read_write);
        start.stored = runs::load_run(*start.resumed);
    }
    auto& config = start.config;
    config = options.config_path.empty()
                 ? runs::EvolveConfig::from_json(start.stored->config, name + " (stored config)", {},
                                                 runs::ConfigOrigin::stored)
                 : runs::EvolveConfig::load(options.config_path);
    // a run keeps the math it was made with: a config given on resume that does not
    // name one takes the run's (an older file's, without the key, is libm)
    if (start.stored && !config.math_given) {
        if (const auto math = runs::stored_math(start.stored->config)) config.set_math(*math);
    }
    if (options.retain) config.retain = *options.retain;
    if (options.generations) config.ea.generations = *options.generations;
    if (options.seed) config.seed = *options.seed;
    apply_transfer_options(config, options, start.stored ? &*start.stored : nullptr);
    if (config.transfer && start.stored && start.stored->config.contains("transfer") &&
        !options.allow_config_change) {
        // resuming: the digests to check the KB and the seed source against are the stored ones
        const auto& stored = start.stored->config["transfer"];
        config.transfer->kb_digest = stored.value("kb_digest", "");
        if (config.transfer->seed) {
            config.transfer->seed->digest =
                stored.contains("seed") ? stored["seed"].value("digest", "") : std::string();
        }
    }
    // messages name the KB as it was given; the stored config holds its absolute path (for resumes)
    const std::string kb_given = config.transfer ? config.transfer->kb.string() : std::string();
    if (config.transfer && !config.transfer->kb.empty()) start.shaping = load_shaping_kb(config);
    if (config.seeding()) {
        // generation 0 alone reads the seeds: a resume past it only checks a source still there
        if (start.stored && start.stored->generations_done >= 0)
            check_seed_source(config);
        else
            start.seeds = load_seeds(config);
    }
    if (start.shaping && needs_kb(config.treatment()) && !(start.shaping->max_average() > 0.0)) {
        std::cerr << "stepstone: warning: " << kb_given
                  << ": the knowledge base's largest average reward is 0, so r_max is 0 for every policy and "
                  << to_string(config.treatment()) << " selects as none would\n";
    }
    return start;
}

// The run file open for writing: the resumed one, or a new one whose run row
// (and empty KB) is written under a temporary name and moved into place whole.
db::Connection open_run_file(const EvolveOptions& options, RunStart& start) {
    if (start.resumed) return std::move(*start.resumed);
    auto& config = start.config;
    {
        db::OutputDatabase output(options.db_path, options.force);
        if (!config.seed) config.seed = fresh_seed() >> 1;
        runs::RunRecord run;
        run.task = std::string(sim::to_string(config.task.kind));
        run.treatment = std::string(to_string(config.run_treatment()));
        run.seed = static_cast<std::int64_t>(*config.seed);
        run.config = config.to_json();
        run.generations = config.ea.generations;
        insert_run(output.connection(), run, full_version());
        db::set_meta_value(output.connection(), kMathFingerprintKey, math_fingerprint());
        if (config.kb)
            db::insert_kb(output.connection(), runs::kRunKbName, kb::KnowledgeBase(kb_params(*config.kb)));
        output.commit();
    }
    return db::open_database(options.db_path, db::OpenMode::read_write);
}

// On resume on a machine whose math library rounds differently from the one
// that started the run: a warning, since the run goes on validly but will not
// equal an uninterrupted run (files of older builds hold no fingerprint). A
// run on portable math does not depend on the library.
void warn_math_change(const EvolveOptions& options, const runs::EvolveConfig& config,
                      db::Connection& connection) {
    if (!options.resume || config.math() == Math::portable) return;
    const std::string stored = db::meta_value(connection, kMathFingerprintKey);
    if (stored.empty() || stored == math_fingerprint()) return;
    std::cerr << "stepstone: warning: " << options.db_path.string()
              << ": this machine's math library rounds differently from the one that started the run "
                 "(math fingerprint "
              << math_fingerprint() << ", the run's " << stored
              << "): the generations from here on will not equal those of an uninterrupted run\n";
}

// On resume: the stored seed unless the user names another one, the config
// compared with the stored one, the stored generation count unless given.
void reconcile_resumed(const EvolveOptions& options, const runs::RunRecord& run, runs::EvolveConfig& config) {
    if (!options.resume) return;
    if (!options.seed && run.config.contains("seed")) config.seed = run.config["seed"].get<std::uint64_t>();
    const std::string diff = first_difference(comparable(run.config), comparable(config.to_json()), "");
    if (!diff.empty() && !options.allow_config_change) {
        throw ConfigError(concat(options.db_path.string(), ": the config differs from the run's at ", diff,
                                 " (use ", option_name("allow_config_change"), " to resume anyway)"));
    }
    if (!options.generations) config.ea.generations = run.generations;
}

// The evolution at the run's last committed generation, with the run's own KB
// (written in the same transactions as the checkpoint, so the two agree) and
// the shaping KB.
void restore_evolution(Evolution& evolution, db::Connection& connection, const runs::RunRecord& run,
                       const runs::EvolveConfig& config, std::optional<kb::KnowledgeBase>& shaping) {
    if (auto state = runs::load_checkpoint(connection, run.id)) evolution.restore(*state);
    if (config.kb) {
        auto stored = db::load_kb(connection, runs::kRunKbName);
        evolution.attach_kb(std::move(stored.kb), stored.id, concat("seed-", run.seed));
    }
    if (shaping) evolution.attach_shaping(std::move(*shaping), config.treatment());
}

// The generations up to `run.generations`, one transaction each. A signal or a
// lost MPI rank stops at a generation's boundary, the file closed with every
// committed generation in it (no -wal / -shm left beside it).
void run_generations(const EvolveOptions& options, db::Connection& connection, runs::RunRecord& run,
                     Evolution& evolution) {
    const std::string name = options.db_path.string();
    const int target = run.generations;
    Progress progress("generation", static_cast<std::uint64_t>(target), options.progress);
    const double started = now_seconds();
    std::int64_t evaluations_here = 0;
    const auto stop = [&](int committed, const std::string& reason) {
        db::finish_writing(connection);
        connection.close();
        const std::string where =
            concat("stopped ",
                   committed < 0 ? std::string("before generation 0")
                                 : concat("after generation ", committed, " of ", target),
                   "; continue with ", option_name("resume"));
        if (!reason.empty()) throw Error(concat(name, ": ", reason, "; ", where));
        throw Interrupted(concat(name, ": ", where));
    };
    const bool was_finished = evolution.generation() >= target;
    while (evolution.generation() < target) {
        const int committed = evolution.generation();
        if (InterruptGuard::received()) stop(committed, options.mpi ? options.mpi->lose() : "");
        runs::GenerationWrite write;
        try {
            write = committed < 0 ? evolution.initialise() : evolution.epoch();
        } catch (const EvaluationInterrupted& e) {
            stop(committed,
                 e.reason);  // the generation in progress is dropped: a resume redoes it identically
        }
        write_generation(connection, run, write);
        evaluations_here += write.stats.evaluations;
        const double elapsed = now_seconds() - started;
        char status[96];
        std::snprintf(status, sizeof status, "best %.4g  %.1f eval/s", write.stats.best_reward,
                      elapsed > 0 ? static_cast<double>(evaluations_here) / elapsed : 0.0);
        progress.update(static_cast<std::uint64_t>(evolution.generation()), status);
    }
    if (!was_finished) progress.finish();
}

}  // namespace

EvolveSummary run_evolve(const EvolveOptions& options) {
    // Ctrl-C and SIGTERM stop at the next generation boundary; taken first, so that a signal
    // while the run is set up (a large KB loads for seconds) stops it there too
    std::optional<InterruptGuard> interrupts;
    if (options.stop_on_signals) interrupts.emplace();
    check_run_file(options);
    const WriterLock lock(options.db_path);  // one writer per run file, refused at once

    RunStart start = load_run_start(options);
    db::Connection connection = open_run_file(options, start);
    runs::RunRecord run = runs::load_run(connection);
    reconcile_resumed(options, run, start.config);
    warn_math_change(options, start.config, connection);
    db::start_writing(connection);

    Evolution evolution(start.config, static_cast<std::uint64_t>(run.seed), options.threads);
    restore_evolution(evolution, connection, run, start.config, start.shaping);
    if (start.seeds && evolution.generation() < 0) evolution.set_seeds(std::move(start.seeds->genomes));
    std::unique_ptr<RemoteEvaluator> remote;
    if (options.mpi) {
        // every rank gets the effective config: the shaping KB by its absolute path and digest
        remote = options.mpi->start(start.config, evolution.shaping_kb(), options.db_path.string());
        evolution.set_remote(remote.get());
    }

    EvolveSummary summary;
    summary.seed = static_cast<std::uint64_t>(run.seed);
    run.generations = start.config.ea.generations;
    summary.was_finished = options.resume && evolution.generation() >= run.generations;
    run.status = runs::RunStatus::running;
    run_generations(options, connection, run, evolution);
    run.status = runs::RunStatus::finished;
    update_run(connection, run);
    db::finish_writing(connection);

    summary.generations_done = run.generations_done;
    summary.evaluations = run.evaluations;
    for (const auto& m : evolution.population())
        summary.best_reward = std::max(summary.best_reward, m.reward);
    return summary;
}

}  // namespace stepstone::exp
