#include "exp/campaign/campaign_cost.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <fstream>

#include "core/error.hpp"
#include "core/progress.hpp"
#include "core/rng.hpp"
#include "core/text.hpp"
#include "db/database.hpp"
#include "db/kb_store.hpp"
#include "exp/campaign/campaign_kb.hpp"
#include "exp/evaluation.hpp"
#include "exp/evolution.hpp"
#include "nn/genome.hpp"
#include "runs/campaign_store.hpp"
#include "runs/run_store.hpp"
#include "runs/treatment.hpp"

namespace stepstone::exp {

namespace fs = std::filesystem;

double RunKindCost::cpu_seconds() const {
    return static_cast<double>(generations + 1) * other_s +
           static_cast<double>(evaluations) * (simulation_s + lookup_s);
}

double RunKindCost::bytes() const {
    return bytes_fixed + static_cast<double>(evaluations) * bytes_per_evaluation +
           static_cast<double>(generations + 1) * bytes_per_generation +
           static_cast<double>(observations) * kb_bytes_per_observation;
}

namespace {

constexpr int kProbeGenerations = 2;  // epochs after generation 0
constexpr std::size_t kProbeBehaviours = 16;

// a temporary folder, removed with what it holds
class ScratchDir {
public:
    ScratchDir() {
        std::string pattern = (fs::temp_directory_path() / "stepstone-cost-XXXXXX").string();
        if (::mkdtemp(pattern.data()) == nullptr)
            throw Error("campaign cost: cannot make a temporary folder");
        path_ = pattern;
    }
    ~ScratchDir() {
        std::error_code ignored;
        fs::remove_all(path_, ignored);
    }
    ScratchDir(const ScratchDir&) = delete;
    ScratchDir& operator=(const ScratchDir&) = delete;
    const fs::path& path() const { return path_; }

private:
    fs::path path_;
};

// Full-length episodes of random perceptrons (no stand-still stop) on one core for about
// `seconds`: seconds per evaluation, steps per second, and a few first-start behaviours.
struct EpisodeProbe {
    double seconds_per_evaluation = 0;
    double steps_per_second = 0;
    std::vector<std::vector<float>> behaviours;
};

EpisodeProbe probe_episodes(const runs::EvolveConfig& config, double seconds) {
    sim::TaskConfig task = config.task;
    task.still_limit = task.steps_per_start * task.starts + 1;
    const auto shared = sim::make_task(task);
    EpisodeProbe probe;
    std::vector<float> behaviour(shared->behaviour_size());
    const double started = now_seconds();
    double steps = 0;
    std::uint64_t k = 0;
    for (; k == 0 || now_seconds() - started < seconds; ++k) {
        Rng rng(0, 0, k, Purpose::initial_genome);
        auto genome = nn::Genome::random_perceptron(config.dnn, rng);
        genome.simplify();
        const bool keep = probe.behaviours.size() < kProbeBehaviours;
        steps += static_cast<double>(evaluate_genome(*shared, genome, config.dnn,
                                                     keep ? std::span<float>(behaviour) : std::span<float>())
                                         .steps);
        if (keep) probe.behaviours.push_back(behaviour);
    }
    const double elapsed = now_seconds() - started;
    probe.seconds_per_evaluation = elapsed / static_cast<double>(k);
    probe.steps_per_second = steps / elapsed;
    return probe;
}

// seconds per r_max lookup of a full-length behaviour in `kb`, over about `seconds`
double probe_lookups(const kb::KnowledgeBase& kb, const std::vector<std::vector<float>>& behaviours,
                     double seconds) {
    const double started = now_seconds();
    std::size_t done = 0;
    double sink = 0;
    while (done < behaviours.size() || now_seconds() - started < seconds) {
        sink += shaped_r_max(kb, behaviours[done % behaviours.size()]);
        ++done;
    }
    if (sink < 0) std::fputc(' ', stderr);  // keeps the lookups from being optimised away
    return (now_seconds() - started) / static_cast<double>(done);
}

// A real run of the step's config in `folder` (one thread, a few generations): what a
// generation costs besides simulation and lookups, and the file's bytes per evaluation.
void probe_generations(const runs::EvolveConfig& config, const fs::path& folder, const std::string& name,
                       RunKindCost& cost) {
    runs::EvolveConfig probe = config;
    probe.transfer.reset();
    probe.seed = 1;
    const fs::path config_path = folder / (name + ".json");
    std::ofstream(config_path) << probe.to_file_json().dump();
    EvolveOptions options;
    options.config_path = config_path;
    options.db_path = folder / (name + ".db");
    options.generations = kProbeGenerations;
    options.threads = 1;
    options.progress = ProgressMode::quiet;
    options.stop_on_signals = false;
    run_evolve(options);
    auto connection = db::open_database(options.db_path, db::OpenMode::read_only);
    const auto file = runs::run_file_cost(connection);
    cost.other_s = std::max(0.0, file.other_s);
    const double evaluations = std::max(1.0, file.evaluations);
    // the file by part: rows per evaluation, genomes per generation, the KB per observation
    // (the probe observes once, at generation 0, when the config has a KB), the rest once
    const double kb = config.kb ? file.kb_bytes : 0.0;  // else empty tables
    cost.bytes_per_evaluation = file.individual_bytes / evaluations;
    cost.bytes_per_generation = file.generation_bytes / (kProbeGenerations + 1);
    cost.kb_bytes_per_observation = kb;
    cost.bytes_fixed = std::max(0.0, file.total_bytes - file.individual_bytes - file.generation_bytes - kb);
    cost.observations = config.kb ? cost.generations / config.kb->period + 1 : 0;
}

// The campaign's KB when it exists: kb.file (coarsened to kb.delta), or kb/kb.db of `dir`.
std::optional<kb::KnowledgeBase> existing_kb(const runs::CampaignConfig& config, const fs::path& dir,
                                             const fs::path& scratch) {
    fs::path file;
    bool coarsen = false;
    if (config.kb_from == runs::KbFrom::file) {
        file = config.kb_file;
        coarsen = config.kb_delta.has_value();
        if (file.extension() == ".gz") {
            const fs::path plain = scratch / "kb.db";
            gunzip_file(file, plain);
            file = plain;
        }
    } else if (!dir.empty() && fs::exists(dir / runs::kKbFile)) {
        file = dir / runs::kKbFile;
    } else {
        return std::nullopt;
    }
    auto connection = db::open_database(file, db::OpenMode::read_only);
    auto stored = db::load_kb(connection, "");
    if (coarsen) return stored.kb.coarsened(*config.kb_delta);
    return std::move(stored.kb);
}

// a run's evaluations: generation 0's initial population, then one population a generation
std::int64_t evaluations_per_run(const runs::RunStep& step) {
    const auto& ea = step.config.ea;
    return static_cast<std::int64_t>(ea.initial_multiplier) * ea.population_size +
           static_cast<std::int64_t>(step.generations) * ea.population_size;
}

RunKindCost kind_of(const runs::RunStep& step, std::string kind, std::int64_t runs) {
    RunKindCost cost;
    cost.kind = std::move(kind);
    cost.runs = runs;
    cost.generations = step.generations;
    cost.evaluations = evaluations_per_run(step);
    return cost;
}

}  // namespace

CampaignCost estimate_cost(const runs::CampaignConfig& config, const fs::path& dir, double probe_seconds) {
    const double started = now_seconds();
    CampaignCost cost;
    auto count = [&](const runs::RunStep& step, std::size_t runs) {
        const auto evaluations = evaluations_per_run(step) * static_cast<std::int64_t>(runs);
        cost.runs += static_cast<std::int64_t>(runs);
        cost.evaluations += evaluations;
        cost.robot_steps +=
            static_cast<double>(evaluations) * step.config.task.starts * step.config.task.steps_per_start;
    };
    if (config.source) count(*config.source, config.source->seeds.size());
    count(config.target, config.target.seeds.size() * config.treatments.size());

    const ScratchDir scratch;
    if (config.source) {
        RunKindCost source =
            kind_of(*config.source, "source", static_cast<std::int64_t>(config.source->seeds.size()));
        const auto episodes = probe_episodes(config.source->config, probe_seconds);
        source.simulation_s = episodes.seconds_per_evaluation;
        probe_generations(config.source->config, scratch.path(), "source", source);
        cost.kinds.push_back(source);
    }
    const auto episodes = probe_episodes(config.target.config, probe_seconds);
    cost.steps_per_second = episodes.steps_per_second;
    RunKindCost unshaped = kind_of(config.target, "", 0);
    unshaped.simulation_s = episodes.seconds_per_evaluation;
    probe_generations(config.target.config, scratch.path(), "target", unshaped);

    // target runs by what they look up: nothing, the KB, or its randomized twin
    const auto seeds = static_cast<std::int64_t>(config.target.seeds.size());
    std::int64_t plain = 0, real = 0, randomized = 0;
    for (const auto treatment : config.treatments) {
        if (!runs::needs_kb(treatment))
            ++plain;
        else if (runs::needs_randomized_kb(treatment))
            ++randomized;
        else
            ++real;
    }
    if (plain > 0) {
        RunKindCost none = unshaped;
        none.kind = "target, unshaped";
        none.runs = plain * seeds;
        cost.kinds.push_back(none);
    }
    const auto kb = (real > 0 || randomized > 0) ? existing_kb(config, dir, scratch.path()) : std::nullopt;
    for (const bool is_randomized : {false, true}) {
        const std::int64_t treatments = is_randomized ? randomized : real;
        if (treatments == 0) continue;
        RunKindCost shaped = unshaped;
        shaped.kind = is_randomized ? "target, randomized KB" : "target, KB";
        shaped.runs = treatments * seeds;
        if (kb) {
            const kb::KnowledgeBase looked_up = is_randomized ? kb->randomized(config.randomize_seed) : *kb;
            shaped.lookup_s = probe_lookups(looked_up, episodes.behaviours, probe_seconds);
        } else {
            shaped.lookups_unknown = true;
        }
        cost.kinds.push_back(shaped);
    }
    for (const auto& kind : cost.kinds) {
        cost.cpu_seconds += static_cast<double>(kind.runs) * kind.cpu_seconds();
        cost.bytes += static_cast<double>(kind.runs) * kind.bytes();
    }
    cost.probe_seconds = now_seconds() - started;
    return cost;
}

namespace {

std::string milliseconds(double seconds) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3g ms", seconds * 1e3);
    return text;
}

std::string megabytes(double bytes) {
    char text[32];
    if (bytes >= 1e9)
        std::snprintf(text, sizeof text, "%.1f GB", bytes / 1e9);
    else
        std::snprintf(text, sizeof text, "%.0f MB", std::max(1.0, bytes / 1e6));
    return text;
}

}  // namespace

void write_plan(std::ostream& out, const runs::CampaignConfig& config, const CampaignCost& cost,
                unsigned jobs) {
    const unsigned workers = resolve_threads(jobs);
    if (config.source) {
        out << "source   " << config.source->seeds.size() << " runs x " << config.source->generations
            << " generations (population " << config.source->config.ea.population_size << ")\n";
    }
    switch (config.kb_from) {
        case runs::KbFrom::best:
            out << "kb       export of the best source run's KB\n";
            break;
        case runs::KbFrom::merge:
            out << "kb       merge of every source run's KB\n";
            break;
        case runs::KbFrom::file:
            out << "kb       copy of " << config.kb_file_given << "\n";
            break;
    }
    if (config.kb_delta) out << "         coarsened to delta " << shortest(*config.kb_delta) << "\n";
    if (config.needs_randomized_kb())
        out << "kb-rand  randomized with seed " << config.randomize_seed << "\n";
    if (config.seeded()) {
        const auto& seed = *config.seed;
        out << "seed     " << runs::to_string(seed.with) << " of "
            << (seed.from_file ? seed.file_given : std::string("the best source run"));
        if (seed.count) out << ", at most " << *seed.count;
        out << "\n";
    }
    out << "target   " << config.treatments.size() << " treatments (";
    for (std::size_t k = 0; k < config.treatments.size(); ++k) {
        out << (k ? ", " : "") << runs::to_string(config.treatments[k]);
    }
    out << ") x " << config.target.seeds.size() << " seeds x " << config.target.generations
        << " generations (population " << config.target.config.ea.population_size << ")\n";
    char line[512];
    std::snprintf(line, sizeof line, "cost     %lld runs, %lld evaluations, at most %.3g robot steps\n",
                  static_cast<long long>(cost.runs), static_cast<long long>(cost.evaluations),
                  cost.robot_steps);
    out << line;
    out << "         estimated from a " << format_duration(cost.probe_seconds)
        << " probe of this machine, one core a run:\n";
    bool unknown = false;
    for (const auto& kind : cost.kinds) {
        std::snprintf(line, sizeof line, "           %-22s %3lld x %lld evaluations: %.2f ms each simulated",
                      kind.kind.c_str(), static_cast<long long>(kind.runs),
                      static_cast<long long>(kind.evaluations), kind.simulation_s * 1e3);
        out << line;
        if (kind.lookup_s > 0) out << concat(" + ", milliseconds(kind.lookup_s), " looked up");
        if (kind.lookups_unknown) out << " + lookups not counted*";
        out << concat(", ", milliseconds(kind.other_s),
                      " a generation besides: ", format_duration(kind.cpu_seconds()), " a run\n");
        unknown = unknown || kind.lookups_unknown;
    }
    out << "         about " << format_duration(cost.cpu_seconds) << " of CPU, "
        << format_duration(cost.cpu_seconds / workers) << " on " << workers << " jobs; run files about "
        << megabytes(cost.bytes) << "\n";
    out << "         (an estimate, not a bound: every evaluation timed at its full length, which policies\n"
           "         that stand still do not reach, lookups timed on random policies' behaviours, and this\n"
           "         machine's speed as it is now; estimates of the replication were -8 % to +25 % off\n"
           "         with its KB timed, -41 % and -10 % without, docs/transfer.md)\n";
    if (unknown) {
        out << "         * the KB is made by the source step: a dry run on the campaign's folder once it\n"
               "           holds kb/kb.db, or a config with kb.file, times the lookups\n";
    }
}

}  // namespace stepstone::exp
