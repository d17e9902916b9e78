#include "exp/campaign.hpp"

#include <fcntl.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <deque>
#include <fstream>
#include <map>
#include <set>
#include <thread>

#include "core/config.hpp"
#include "core/error.hpp"
#include "core/output_file.hpp"
#include "core/rng.hpp"
#include "core/text.hpp"
#include "core/writer_lock.hpp"
#include "db/database.hpp"
#include "db/digest.hpp"
#include "db/kb_store.hpp"
#include "exp/evaluation.hpp"
#include "exp/kb_files.hpp"
#include "exp/run_store.hpp"
#include "nn/genome.hpp"

namespace stepstone::exp {

namespace fs = std::filesystem;

namespace {

constexpr const char* kCampaignFile = "campaign.db";
constexpr const char* kKbFile = "kb/kb.db";
constexpr const char* kRandomKbFile = "kb/kb-rand.db";

// ------------------------------------------------------------------- config

std::vector<std::uint64_t> read_seeds(JsonReader& reader) {
    std::vector<std::uint64_t> seeds;
    if (reader.has("seeds")) {
        if (reader.has("runs") || reader.has("first_seed")) {
            throw ConfigError(concat(reader.path_of("seeds"), " cannot be combined with runs or first_seed"));
        }
        const auto& raw = reader.raw("seeds");
        if (!raw.is_array() || raw.empty()) {
            throw ConfigError(concat(reader.path_of("seeds"), " must be a non-empty array of seeds"));
        }
        for (const auto& seed : raw) {
            if (!seed.is_number_integer() || seed.get<std::int64_t>() < 0) {
                throw ConfigError(concat(reader.path_of("seeds"), " holds ", describe(seed),
                                         "; seeds are integers >= 0"));
            }
            seeds.push_back(seed.get<std::uint64_t>());
        }
        std::set<std::uint64_t> unique(seeds.begin(), seeds.end());
        if (unique.size() != seeds.size()) throw ConfigError(concat(reader.path_of("seeds"), " repeats a seed"));
        return seeds;
    }
    int runs = 1;
    std::int64_t first = 1;
    reader.read("runs", runs, 1, 1000000);
    reader.read("first_seed", first, 0, kMaxSeed - 1000000);
    for (int k = 0; k < runs; ++k) seeds.push_back(static_cast<std::uint64_t>(first + k));
    return seeds;
}

RunStep read_step(JsonReader& reader, const fs::path& base) {
    RunStep step;
    const auto& raw = reader.raw("config");
    if (raw.is_string()) {
        step.config = EvolveConfig::load(base / raw.get<std::string>());
    } else if (raw.is_object()) {
        step.config = EvolveConfig::from_json(raw, reader.path_of("config"));
    } else {
        throw ConfigError(concat(reader.path_of("config"),
                                 raw.is_null() ? " is required" : " must be a file name or an evolve config object"));
    }
    if (step.config.transfer) {
        throw ConfigError(concat(reader.path_of("config"),
                                 " must not hold a transfer block: the campaign sets each run's KB and treatment"));
    }
    step.config.seed.reset();  // each run gets its own
    step.seeds = read_seeds(reader);
    reader.read("generations", step.config.ea.generations, 0, 100000000);
    step.generations = step.config.ea.generations;
    return step;
}

nlohmann::json step_json(const RunStep& step) {
    return {{"config", step.config.to_json()}, {"seeds", step.seeds}, {"generations", step.generations}};
}

std::string seed_file(std::uint64_t seed) { return concat("seed-", seed, ".db"); }

// -------------------------------------------------------------- campaign.db

struct RunState {
    PlannedRun run;
    std::int64_t id = 0;
    RunStatus status = RunStatus::pending;
    int generations_done = -1;
    std::optional<double> best_reward;
};

// What a run file says about itself; nullopt when it does not exist.
struct RunFileState {
    bool finished = false;
    int generations_done = -1;
    double best_reward = 0;
};

std::optional<RunFileState> read_run_file(const fs::path& path) {
    if (!fs::exists(path)) return std::nullopt;
    auto connection = db::open_database(path, db::OpenMode::read_only);
    const RunRecord run = load_run(connection);
    RunFileState state;
    state.generations_done = run.generations_done;
    state.finished = run.status == RunStatus::finished;
    auto best = connection.prepare(db::sql("run/max_best_reward.sql"));
    if (best.step() && best.column_type(0) != db::Statement::Type::null) state.best_reward = best.column_double(0);
    return state;
}

void update_run_row(db::Connection& connection, const RunState& state, const std::optional<std::string>& digest,
                    double wall_time, const std::optional<std::string>& error) {
    auto update = connection.prepare(db::sql("campaign/update_run.sql"));
    update.bind(":status", to_string(state.status))
        .bind(":generations_done", state.generations_done)
        .bind(":best_reward", state.best_reward)
        .bind(":digest", digest)
        .bind(":wall_time", wall_time)
        .bind(":error", error)
        .bind(":id", state.id);
    update.step();
}

std::string last_line_of(const fs::path& log) {
    std::ifstream in(log);
    std::string line, last;
    while (std::getline(in, line)) {
        if (!line.empty()) last = line;
    }
    return last.empty() ? std::string("no output") : last;
}

// ------------------------------------------------------------------ runner

class Runner {
public:
    Runner(const CampaignOptions& options, db::Connection& connection, std::vector<RunState>& runs,
           Progress& progress)
        : options_(options), connection_(connection), runs_(runs), progress_(progress) {
        jobs_ = resolve_threads(options.jobs);
    }

    // Runs the given runs to the end, `jobs` at a time; returns the failures.
    std::vector<std::string> execute(const std::vector<std::size_t>& indices, CampaignSummary& summary) {
        std::deque<std::size_t> queue;
        for (std::size_t k : indices) {
            auto& state = runs_[k];
            const fs::path file = options_.dir / state.run.file;
            if (state.status == RunStatus::finished && !fs::exists(file)) {
                std::fprintf(stderr, "campaign: %s is missing though campaign.db records it finished; running it again\n",
                             state.run.file.c_str());
            }
            const auto on_disk = existing_state(k);
            if (on_disk && on_disk->finished && on_disk->generations_done >= state.run.generations) {
                mark_finished(k, *on_disk, 0.0);
                ++summary.skipped;
                continue;
            }
            queue.push_back(k);
        }
        // results do not depend on threads: idle cores go to the runs of a small step
        const std::size_t at_once = std::max<std::size_t>(1, std::min(jobs_, queue.size()));
        threads_ = options_.threads > 0 ? options_.threads
                                        : std::max(1u, resolve_threads(0) / static_cast<unsigned>(at_once));
        std::vector<std::string> failures;
        std::map<pid_t, Active> active;
        while (!queue.empty() || !active.empty()) {
            while (!queue.empty() && active.size() < jobs_) {
                const std::size_t k = queue.front();
                queue.pop_front();
                active.emplace(launch(k), Active{k, now_seconds()});
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(100));
            for (;;) {
                int status = 0;
                const pid_t pid = ::waitpid(-1, &status, WNOHANG);
                if (pid <= 0) break;
                const auto it = active.find(pid);
                if (it == active.end()) continue;
                const Active done = it->second;
                active.erase(it);
                if (auto failure = finish(done, status)) failures.push_back(*failure);
            }
            report(active);
        }
        return failures;
    }

private:
    struct Active {
        std::size_t index = 0;
        double started = 0;
    };

    std::optional<RunFileState> existing_state(std::size_t k) {
        try {
            return read_run_file(options_.dir / runs_[k].run.file);
        } catch (const Error&) {
            return RunFileState{};  // present but unreadable: evolve --resume reports why
        }
    }

    void mark_finished(std::size_t k, const RunFileState& on_disk, double wall_time) {
        auto& state = runs_[k];
        state.status = RunStatus::finished;
        state.generations_done = on_disk.generations_done;
        state.best_reward = on_disk.best_reward;
        auto run_connection = db::open_database(options_.dir / state.run.file, db::OpenMode::read_only);
        update_run_row(connection_, state, db::run_digest(run_connection), wall_time, std::nullopt);
    }

    pid_t launch(std::size_t k) {
        auto& state = runs_[k];
        const fs::path file = options_.dir / state.run.file;
        fs::create_directories(file.parent_path());
        fs::create_directories(options_.dir / "logs");
        const fs::path log = log_path(state.run);
        std::vector<std::string> args = {
            options_.program.string(),
            "evolve",
            "--config",
            (options_.dir / "config" / concat(to_string(state.run.step), ".json")).string(),
            "--db",
            file.string(),
            "--seed",
            std::to_string(state.run.seed),
            "--generations",
            std::to_string(state.run.generations),
            "--threads",
            std::to_string(threads_),
            "--quiet"};
        if (fs::exists(file)) args.emplace_back("--resume");
        if (state.run.step == CampaignStep::target && needs_kb(state.run.treatment)) {
            args.emplace_back("--kb");
            args.push_back((options_.dir / (needs_randomized_kb(state.run.treatment) ? kRandomKbFile : kKbFile)).string());
            args.emplace_back("--treatment");
            args.emplace_back(to_string(state.run.treatment));
        }
        std::vector<char*> argv;
        for (auto& arg : args) argv.push_back(arg.data());
        argv.push_back(nullptr);

        const pid_t parent = ::getpid();
        std::fflush(nullptr);
        const pid_t pid = ::fork();
        if (pid < 0) throw Error(concat("campaign: cannot start a run: fork failed"));
        if (pid == 0) {
            // the run dies with the campaign: a killed campaign leaves no run writing behind its back
            // (SIGKILL, not SIGTERM, which evolve would take as "stop after this generation" and keep
            // its writer lock that long, refusing a campaign resumed at once)
            ::prctl(PR_SET_PDEATHSIG, SIGKILL);
            if (::getppid() != parent) ::_exit(125);
            const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
            if (fd >= 0) {
                ::dup2(fd, STDOUT_FILENO);
                ::dup2(fd, STDERR_FILENO);
                ::close(fd);
            }
            ::execv(argv[0], argv.data());
            ::_exit(127);
        }
        state.status = RunStatus::running;
        update_run_row(connection_, state, std::nullopt, 0.0, std::nullopt);
        return pid;
    }

    std::optional<std::string> finish(const Active& done, int status) {
        auto& state = runs_[done.index];
        const double wall = now_seconds() - done.started;
        const bool ok = WIFEXITED(status) && WEXITSTATUS(status) == 0;
        if (ok) {
            try {
                const auto on_disk = read_run_file(options_.dir / state.run.file);
                if (on_disk && on_disk->finished) {
                    mark_finished(done.index, *on_disk, wall);
                    return std::nullopt;
                }
            } catch (const Error&) {
            }
        }
        std::string error = WIFSIGNALED(status) ? concat("killed by signal ", WTERMSIG(status))
                                                : last_line_of(log_path(state.run));
        state.status = RunStatus::failed;
        update_run_row(connection_, state, std::nullopt, wall, error);
        return concat(state.run.file, ": ", error);
    }

    void report(const std::map<pid_t, Active>& active) {
        std::uint64_t done = 0;
        std::size_t finished = 0;
        for (std::size_t k = 0; k < runs_.size(); ++k) {
            auto& state = runs_[k];
            if (state.status == RunStatus::running) {
                try {
                    if (auto on_disk = read_run_file(options_.dir / state.run.file)) {
                        state.generations_done = on_disk->generations_done;
                    }
                } catch (const Error&) {
                    // being created or busy: keep the last reading
                }
            }
            if (state.status == RunStatus::finished) ++finished;
            done += static_cast<std::uint64_t>(std::max(0, state.generations_done + 1));
        }
        std::string status = concat("runs ", finished, "/", runs_.size());
        for (const auto& [pid, run] : active) {
            const auto& state = runs_[run.index];
            status += concat("  ",
                             state.run.step == CampaignStep::source ? to_string(state.run.step)
                                                                    : to_string(state.run.treatment),
                             "/", state.run.seed, " g", std::max(0, state.generations_done), "/",
                             state.run.generations);
        }
        progress_.update(done, status);
    }

    fs::path log_path(const PlannedRun& run) const {
        std::string name = run.file;
        std::replace(name.begin(), name.end(), '/', '-');
        return options_.dir / "logs" / (fs::path(name).replace_extension(".log"));
    }

    const CampaignOptions& options_;
    db::Connection& connection_;
    std::vector<RunState>& runs_;
    Progress& progress_;
    std::size_t jobs_ = 1;
    unsigned threads_ = 1;  // evaluation threads of each run of the step in progress
};

// -------------------------------------------------------------------- KB step

void record_kb(db::Connection& connection, const std::string& name, const std::string& file,
               const std::string& made_from, const fs::path& path) {
    auto kb_connection = db::open_database(path, db::OpenMode::read_only);
    const auto stored = db::load_kb(kb_connection);
    auto upsert = connection.prepare(db::sql("campaign/upsert_kb.sql"));
    upsert.bind(":name", name)
        .bind(":file", file)
        .bind(":made_from", made_from)
        .bind(":segments", static_cast<std::int64_t>(stored.kb.size()))
        .bind(":digest", db::kb_digest(stored.kb, stored.randomized_seed));
    upsert.step();
}

}  // namespace

void gunzip_file(const fs::path& in, const fs::path& out) {
    gzFile file = gzopen(in.c_str(), "rb");
    if (file == nullptr) throw DataError(concat(in.string(), ": cannot be opened"));
    if (gzdirect(file) == 1) {  // zlib would pass plain bytes through
        gzclose(file);
        throw DataError(concat(in.string(), ": not whole gzip data"));
    }
    std::ofstream target(out, std::ios::binary | std::ios::trunc);
    if (!target) {
        gzclose(file);
        throw Error(concat("cannot write ", out.string()));
    }
    char buffer[1 << 16];
    int read = 0;
    while ((read = gzread(file, buffer, sizeof buffer)) > 0) target.write(buffer, read);
    int code = Z_OK;
    const bool failed = read < 0 || (gzerror(file, &code), code != Z_OK && code != Z_STREAM_END);
    gzclose(file);
    target.close();
    if (failed || !target) {
        fs::remove(out);
        throw DataError(concat(in.string(), ": not whole gzip data"));
    }
}

namespace {

void make_kbs(const CampaignOptions& options, const CampaignConfig& config, db::Connection& connection,
              const std::vector<RunState>& runs) {
    const fs::path kb_path = options.dir / kKbFile;
    fs::create_directories(kb_path.parent_path());
    std::string made_from;
    if (config.kb_from == KbFrom::file) {
        if (config.kb_file.extension() == ".gz") {
            // a compressed KB (the demo's fixture): copied from its uncompressed form
            const fs::path plain = kb_path.parent_path() / ".kb-file-uncompressed.db";
            gunzip_file(config.kb_file, plain);
            try {
                export_kb(plain, "", kb_path, true);
            } catch (...) {
                fs::remove(plain);
                throw;
            }
            fs::remove(plain);
        } else {
            export_kb(config.kb_file, "", kb_path, true);
        }
        made_from = concat("copy of ", config.kb_file.string());
    } else {
        std::vector<const RunState*> sources;
        for (const auto& state : runs) {
            if (state.run.step == CampaignStep::source) sources.push_back(&state);
        }
        if (config.kb_from == KbFrom::best || sources.size() == 1) {
            const RunState* best = sources.front();
            for (const RunState* state : sources) {
                const double r = state->best_reward.value_or(0), b = best->best_reward.value_or(0);
                if (r > b || (r == b && state->run.seed < best->run.seed)) best = state;
            }
            export_kb(options.dir / best->run.file, kRunKbName, kb_path, true);
            made_from = concat("best source run ", best->run.file, " (reward ", best->best_reward.value_or(0), ")");
        } else {
            std::vector<fs::path> inputs;
            for (const RunState* state : sources) inputs.push_back(options.dir / state->run.file);
            merge_kb_files(inputs, kb_path, "kb", true, kRunKbName);
            made_from = concat("merge of ", inputs.size(), " source runs");
        }
    }
    if (config.kb_delta) {
        // re-observed under the larger delta (kb export --delta), then put in place
        const fs::path coarse = options.dir / (std::string(kKbFile) + ".coarse");
        export_kb(kb_path, "", coarse, true, config.kb_delta);
        fs::rename(coarse, kb_path);
        made_from += concat(", coarsened to delta ", shortest(*config.kb_delta));
    }
    record_kb(connection, "kb", kKbFile, made_from, kb_path);
    if (config.needs_randomized_kb()) {
        randomize_kb_file(kb_path, options.dir / kRandomKbFile, config.randomize_seed, "", true);
        record_kb(connection, "kb-rand", kRandomKbFile, concat("randomize ", kKbFile, " seed ", config.randomize_seed),
                  options.dir / kRandomKbFile);
    }
}

void write_step_config(const fs::path& path, const RunStep& step) {
    nlohmann::json json = step.config.to_json();
    json["ea"]["generations"] = step.generations;
    OutputFile out(path, true);
    out.stream() << json.dump(2) << "\n";
    out.commit();
}

}  // namespace

// ------------------------------------------------------------------- config

CampaignConfig CampaignConfig::from_json(const nlohmann::json& json, const std::string& source_name,
                                         const fs::path& base) {
    try {
        JsonReader root(json, "");
        CampaignConfig config;
        if (root.has("source")) {
            JsonReader source = root.child("source");
            config.source = read_step(source, base);
            source.finish();
        }
        {
            JsonReader kb = root.child("kb");
            if (kb.has("file")) {
                if (kb.has("from")) throw ConfigError("kb.from and kb.file cannot both be given");
                std::string file;
                kb.read("file", file);
                config.kb_from = KbFrom::file;
                config.kb_file = fs::absolute(base / file).lexically_normal();
            } else {
                std::string from = "best";
                kb.read_choice("from", from, {"best", "merge"});
                config.kb_from = from == "merge" ? KbFrom::merge : KbFrom::best;
            }
            if (kb.has("delta")) {
                double delta = 0.0;
                kb.read("delta", delta, 1e-9, 1e9);
                config.kb_delta = delta;
            }
            kb.finish();
        }
        std::int64_t randomize_seed = 1;
        root.read("randomize_seed", randomize_seed, 0, kMaxSeed);
        config.randomize_seed = static_cast<std::uint64_t>(randomize_seed);

        JsonReader target = root.child("target");
        if (!root.has("target")) throw ConfigError("target is required");
        const auto& treatments = target.raw("treatments");
        if (treatments.is_null()) {
            config.treatments.assign(all_treatments().begin(), all_treatments().end());
        } else {
            if (!treatments.is_array() || treatments.empty()) {
                throw ConfigError("target.treatments must be a non-empty array of treatment names");
            }
            for (const auto& name : treatments) {
                if (!name.is_string()) throw ConfigError(concat("target.treatments holds ", describe(name)));
                const Treatment t = parse_treatment(name.get<std::string>(), "target.treatments");
                if (std::find(config.treatments.begin(), config.treatments.end(), t) != config.treatments.end()) {
                    throw ConfigError(concat("target.treatments names ", to_string(t), " twice"));
                }
                config.treatments.push_back(t);
            }
        }
        config.target = read_step(target, base);
        target.finish();
        root.finish();

        const bool kb_needed = config.needs_kb();
        if (kb_needed && config.kb_from != KbFrom::file) {
            if (!config.source) {
                throw ConfigError("a campaign without a source step needs kb.file (the KB the treatments use)");
            }
            if (!config.source->config.kb) {
                throw ConfigError("source.config has no kb block: the source runs would build no knowledge base");
            }
        }
        if (kb_needed && config.kb_from == KbFrom::file && !fs::exists(config.kb_file)) {
            throw ConfigError(concat("kb.file: ", config.kb_file.string(), " does not exist"));
        }
        return config;
    } catch (const ConfigError& e) {
        throw ConfigError(concat(source_name, ": ", e.what()));
    }
}

CampaignConfig CampaignConfig::load(const fs::path& path) {
    const nlohmann::json json = load_json_file(path);
    if (json.is_object() && !json.contains("target") && (json.contains("task") || json.contains("ea"))) {
        throw ConfigError(concat(path.string(), ": this is a run config, not a campaign config (run it with: "
                                                "stepstone evolve --config ", path.string(), " --db RUN.db)"));
    }
    return from_json(json, path.string(), path.parent_path());
}

nlohmann::json CampaignConfig::to_json() const {
    nlohmann::json json;
    if (source) json["source"] = step_json(*source);
    if (kb_from == KbFrom::file) {
        json["kb"] = {{"file", kb_file.string()}};
    } else {
        json["kb"] = {{"from", kb_from == KbFrom::merge ? "merge" : "best"}};
    }
    if (kb_delta) json["kb"]["delta"] = *kb_delta;
    json["randomize_seed"] = randomize_seed;
    json["target"] = step_json(target);
    auto names = nlohmann::json::array();
    for (Treatment t : treatments) names.push_back(to_string(t));
    json["target"]["treatments"] = names;
    return json;
}

bool CampaignConfig::needs_kb() const { return std::any_of(treatments.begin(), treatments.end(), exp::needs_kb); }

bool CampaignConfig::needs_randomized_kb() const {
    return std::any_of(treatments.begin(), treatments.end(), exp::needs_randomized_kb);
}

std::vector<PlannedRun> plan_runs(const CampaignConfig& config) {
    std::vector<PlannedRun> runs;
    if (config.source) {
        for (std::uint64_t seed : config.source->seeds) {
            runs.push_back({CampaignStep::source, Treatment::none, seed, "source/" + seed_file(seed),
                            config.source->generations});
        }
    }
    // seed-major: an interrupted campaign leaves every treatment with as many finished runs
    for (std::uint64_t seed : config.target.seeds) {
        for (Treatment t : config.treatments) {
            runs.push_back({CampaignStep::target, t, seed,
                            concat("target/", to_string(t), "/", seed_file(seed)),
                            config.target.generations});
        }
    }
    return runs;
}

// --------------------------------------------------------------------- cost

CampaignCost estimate_cost(const CampaignConfig& config, double measure_seconds) {
    CampaignCost cost;
    auto add = [&](const RunStep& step, std::size_t runs) {
        const auto& ea = step.config.ea;
        const std::int64_t per_run = static_cast<std::int64_t>(ea.initial_multiplier) * ea.population_size +
                                     static_cast<std::int64_t>(step.generations) * ea.population_size;
        const auto evaluations = per_run * static_cast<std::int64_t>(runs);
        cost.runs += static_cast<std::int64_t>(runs);
        cost.evaluations += evaluations;
        cost.robot_steps += static_cast<double>(evaluations) * step.config.task.starts * step.config.task.steps_per_start;
    };
    if (config.source) add(*config.source, config.source->seeds.size());
    add(config.target, config.target.seeds.size() * config.treatments.size());

    // full-length episodes of random perceptrons (no stand-still stop), on one core
    sim::TaskConfig task = config.target.config.task;
    task.still_limit = task.steps_per_start * task.starts + 1;
    const auto shared = sim::make_task(task);
    const double started = now_seconds();
    double steps = 0;
    for (std::uint64_t k = 0; steps == 0 || now_seconds() - started < measure_seconds; ++k) {
        Rng rng(0, 0, k, Purpose::initial_genome);
        auto genome = nn::Genome::random_perceptron(config.target.config.dnn, rng);
        genome.simplify();
        steps += static_cast<double>(evaluate_genome(*shared, genome, config.target.config.dnn).steps);
    }
    cost.steps_per_second = steps / (now_seconds() - started);
    cost.cpu_seconds = cost.robot_steps / cost.steps_per_second;
    return cost;
}

void write_plan(std::ostream& out, const CampaignConfig& config, const CampaignCost& cost, unsigned jobs) {
    const unsigned workers = resolve_threads(jobs);
    if (config.source) {
        out << "source   " << config.source->seeds.size() << " runs x " << config.source->generations
            << " generations (population " << config.source->config.ea.population_size << ")\n";
    }
    switch (config.kb_from) {
        case KbFrom::best: out << "kb       export of the best source run's KB\n"; break;
        case KbFrom::merge: out << "kb       merge of every source run's KB\n"; break;
        case KbFrom::file: out << "kb       copy of " << config.kb_file.string() << "\n"; break;
    }
    if (config.kb_delta) out << "         coarsened to delta " << shortest(*config.kb_delta) << "\n";
    if (config.needs_randomized_kb()) out << "kb-rand  randomized with seed " << config.randomize_seed << "\n";
    out << "target   " << config.treatments.size() << " treatments (";
    for (std::size_t k = 0; k < config.treatments.size(); ++k) {
        out << (k ? ", " : "") << to_string(config.treatments[k]);
    }
    out << ") x " << config.target.seeds.size() << " seeds x " << config.target.generations
        << " generations (population " << config.target.config.ea.population_size << ")\n";
    char line[512];
    std::snprintf(line, sizeof line,
                  "cost     %lld runs, %lld evaluations, at most %.3g robot steps\n"
                  "         at %.3g steps/s per core (measured now): at most %s of CPU, %s on %u jobs\n"
                  "         (an upper bound: policies that stand still stop early; diversity and KB time not counted)\n",
                  static_cast<long long>(cost.runs), static_cast<long long>(cost.evaluations), cost.robot_steps,
                  cost.steps_per_second, format_duration(cost.cpu_seconds).c_str(),
                  format_duration(cost.cpu_seconds / workers).c_str(), workers);
    out << line;
}

// ----------------------------------------------------------------- campaign

CampaignIndex load_campaign(const fs::path& dir) {
    const fs::path path = dir / kCampaignFile;
    if (!fs::exists(path)) {
        const bool demo = fs::exists(dir / "campaign" / kCampaignFile);
        throw DataError(concat(dir.string(), ": no campaign here (", kCampaignFile, " is missing)",
                               demo ? concat("; the campaign is in ", (dir / "campaign").string()) : ""));
    }
    auto connection = db::open_database(path, db::OpenMode::read_only);
    CampaignIndex index;
    auto config = connection.prepare(db::sql("campaign/select_config.sql"));
    if (!config.step()) throw DataError(concat(path.string(), ": holds no campaign"));
    try {
        index.config = nlohmann::json::parse(config.column_text(0));
    } catch (const nlohmann::json::exception& e) {
        throw DataError(concat(path.string(), ": the stored campaign config is malformed: ", one_line(e.what())));
    }
    auto runs = connection.prepare(db::sql("campaign/select_runs.sql"));
    while (runs.step()) {
        PlannedRun run;
        run.step =
            parse_campaign_step(runs.column_text(runs.column("step")), path.string() + ": campaign_run.step");
        run.treatment = parse_treatment(runs.column_text(runs.column("treatment")), "campaign_run.treatment");
        run.seed = static_cast<std::uint64_t>(runs.column_int(runs.column("seed")));
        run.file = runs.column_text(runs.column("file"));
        run.generations = static_cast<int>(runs.column_int(runs.column("generations")));
        index.runs.push_back({run, parse_run_status(runs.column_text(runs.column("status")),
                                                    path.string() + ": campaign_run.status")});
    }
    return index;
}

void throw_on_failures(const CampaignSummary& summary, const fs::path& dir, std::ostream& err) {
    if (summary.failures.empty()) return;
    for (const auto& failure : summary.failures) err << "campaign: failed: " << failure << "\n";
    throw Error(concat(summary.failures.size(), " run(s) failed (logs in ", (dir / "logs").string(),
                       "); fix the cause and resume the campaign"));
}

CampaignSummary run_campaign(const CampaignOptions& given) {
    CampaignOptions options = given;
    if (options.program.empty()) options.program = fs::read_symlink("/proc/self/exe");
    const CampaignConfig config = CampaignConfig::load(options.config_path);
    const auto plan = plan_runs(config);
    const fs::path campaign_path = options.dir / kCampaignFile;
    const std::string dir_name = options.dir.string();
    if (fs::exists(options.dir) && !fs::is_directory(options.dir)) {
        throw ConfigError(concat(dir_name, ": exists and is not a directory (--dir names the campaign's folder)"));
    }
    if (!options.resume && fs::exists(campaign_path)) {
        throw ConfigError(
            concat(dir_name, " already holds a campaign (", kCampaignFile, "); add --resume to continue it"));
    }
    if (options.resume && !fs::exists(campaign_path)) {
        throw ConfigError(concat(dir_name, " holds no ", kCampaignFile, "; run without --resume to start it"));
    }
    fs::create_directories(options.dir);
    const WriterLock lock(campaign_path);  // one campaign process per folder

    if (!options.resume) {
        if (fs::exists(campaign_path)) {
            throw ConfigError(concat(dir_name, " already holds a campaign (", kCampaignFile,
                                     "); add --resume to continue it"));
        }
        fs::create_directories(options.dir);
        db::OutputDatabase output(campaign_path, false);
        auto& connection = output.connection();
        connection.prepare(db::sql("campaign/insert_campaign.sql"))
            .bind(":config", config.to_json().dump())
            .step();
        {
            auto insert = connection.prepare(db::sql("campaign/insert_run.sql"));
            for (std::size_t k = 0; k < plan.size(); ++k) {
                insert.reset();
                insert.bind(":id", static_cast<std::int64_t>(k + 1))
                    .bind(":step", to_string(plan[k].step))
                    .bind(":treatment", to_string(plan[k].treatment))
                    .bind(":seed", static_cast<std::int64_t>(plan[k].seed))
                    .bind(":file", plan[k].file)
                    .bind(":generations", plan[k].generations)
                    .step();
            }
        }  // the statement is finalized before the file is moved into place
        output.commit();
    } else if (!fs::exists(campaign_path)) {
        throw ConfigError(concat(dir_name, " holds no ", kCampaignFile, "; run without --resume to start it"));
    }
    if (options.resume) {
        // a campaign killed in the middle of a write leaves a hot journal that only a writer can
        // roll back: open it for writing once before the read-only loads
        db::open_database(campaign_path, db::OpenMode::read_write).query_int(db::sql("campaign/count.sql"));
    }
    const auto index = load_campaign(options.dir);
    if (options.resume) {
        const std::string diff = first_difference(index.config, config.to_json());
        if (!diff.empty()) {
            throw ConfigError(concat(dir_name, ": the config differs from the campaign's at ", diff));
        }
    }

    fs::create_directories(options.dir / "config");
    if (config.source) write_step_config(options.dir / "config" / "source.json", *config.source);
    write_step_config(options.dir / "config" / "target.json", config.target);

    db::Connection connection = db::open_database(campaign_path, db::OpenMode::read_write);
    std::vector<RunState> runs;
    for (std::size_t k = 0; k < index.runs.size(); ++k) {
        RunState state;
        state.run = index.runs[k].run;
        state.id = static_cast<std::int64_t>(k + 1);
        state.status = index.runs[k].status;
        runs.push_back(state);
    }

    std::uint64_t total = 0;
    for (const auto& state : runs) total += static_cast<std::uint64_t>(state.run.generations + 1);
    Progress progress("generation", total, options.progress);
    CampaignSummary summary;
    summary.runs = runs.size();
    const double started = now_seconds();
    Runner runner(options, connection, runs, progress);

    std::vector<std::size_t> sources, targets;
    for (std::size_t k = 0; k < runs.size(); ++k)
        (runs[k].run.step == CampaignStep::source ? sources : targets).push_back(k);
    summary.failures = runner.execute(sources, summary);
    if (summary.failures.empty()) {
        if (config.needs_kb()) make_kbs(options, config, connection, runs);
        summary.failures = runner.execute(targets, summary);
    }
    for (const auto& state : runs) summary.finished += state.status == RunStatus::finished ? 1 : 0;
    summary.wall_time = now_seconds() - started;
    progress.finish(concat("runs ", summary.finished, "/", summary.runs));
    return summary;
}

}  // namespace stepstone::exp
