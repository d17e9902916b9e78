#include "runs/campaign_config.hpp"

#include <algorithm>
#include <set>

#include "core/config.hpp"
#include "core/error.hpp"
#include "core/output_file.hpp"
#include "core/text.hpp"

namespace stepstone::runs {

namespace fs = std::filesystem;

namespace {

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
                throw ConfigError(
                    concat(reader.path_of("seeds"), " holds ", describe(seed), "; seeds are integers >= 0"));
            }
            seeds.push_back(seed.get<std::uint64_t>());
        }
        std::set<std::uint64_t> unique(seeds.begin(), seeds.end());
        if (unique.size() != seeds.size())
            throw ConfigError(concat(reader.path_of("seeds"), " repeats a seed"));
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
        step.config = EvolveConfig::from_json(raw, reader.path_of("config"), base);
    } else {
        throw ConfigError(
            concat(reader.path_of("config"),
                   raw.is_null() ? " is required" : " must be a file name or an evolve config object"));
    }
    if (step.config.transfer) {
        throw ConfigError(
            concat(reader.path_of("config"),
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

// the seed block: {"from": "best"} or {"file": RUN.db}, with "with" and "count"
CampaignSeed read_campaign_seed(JsonReader reader, const fs::path& base) {
    CampaignSeed seed;
    if (reader.has("file")) {
        if (reader.has("from")) throw ConfigError("seed.from and seed.file cannot both be given");
        reader.read("file", seed.file_given);
        if (seed.file_given.empty()) throw ConfigError("seed.file must name a run file");
        seed.from_file = true;
        seed.file = fs::absolute(base / seed.file_given).lexically_normal();
    } else {
        std::string from = "best";
        reader.read_choice("from", from, {"best"});
    }
    std::string with(to_string(seed.with));
    reader.read_choice("with", with, {"population", "front", "best"});
    seed.with = parse_seed_with(with, reader.path_of("with"));
    if (reader.has("count")) {
        int count = 0;
        reader.read("count", count, -1000000000, 1000000000);
        if (count <= 0) throw ConfigError(concat(reader.path_of("count"), " must be >= 1, got ", count));
        seed.count = count;
    }
    reader.finish();
    return seed;
}

// the seeded treatments' source: a source step to take the best run of, or an existing file
void check_seeding(CampaignConfig& config) {
    if (!config.seeded()) return;
    if (!config.seed) config.seed = CampaignSeed{};
    const CampaignSeed& seed = *config.seed;
    if (seed.from_file) {
        if (!fs::exists(seed.file)) {
            throw ConfigError(concat("seed.file: ", seed.file_given, " does not exist (looked for ",
                                     seed.file.string(), ")"));
        }
        return;
    }
    if (!config.source) {
        throw ConfigError(
            "a seeded treatment needs a source step (seed.from best) or seed.file (the run that seeds)");
    }
    if (seed.with == SeedWith::population &&
        config.source->config.ea.population_size != config.target.config.ea.population_size) {
        throw ConfigError(concat("seed.with population needs one population size: source.config's is ",
                                 config.source->config.ea.population_size, ", target.config's ",
                                 config.target.config.ea.population_size, " (seed with front or best)"));
    }
}

}  // namespace

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
                config.kb_file_given = file;
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
        if (root.has("seed")) config.seed = read_campaign_seed(root.child("seed"), base);
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
                if (std::find(config.treatments.begin(), config.treatments.end(), t) !=
                    config.treatments.end()) {
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
                throw ConfigError(
                    "a campaign without a source step needs kb.file (the KB the treatments use)");
            }
            if (!config.source->config.kb) {
                throw ConfigError(
                    "source.config has no kb block: the source runs would build no knowledge base");
            }
        }
        if (kb_needed && config.kb_from == KbFrom::file && !fs::exists(config.kb_file)) {
            throw ConfigError(concat("kb.file: ", config.kb_file_given, " does not exist (looked for ",
                                     config.kb_file.string(), ")"));
        }
        check_seeding(config);
        return config;
    } catch (const ConfigError& e) {
        throw ConfigError(concat(source_name, ": ", e.what()));
    }
}

CampaignConfig CampaignConfig::load(const fs::path& path) {
    const nlohmann::json json = load_json_file(path);
    if (json.is_object() && !json.contains("target") && (json.contains("task") || json.contains("ea"))) {
        throw ConfigError(
            concat(path.string(), ": this is a run config, not a campaign config (run it as a single run)"));
    }
    return from_json(json, path.string(), path.parent_path());
}

nlohmann::json CampaignConfig::to_json() const {
    nlohmann::json json;
    if (source) json["source"] = step_json(*source);
    if (kb_from == KbFrom::file) {
        // as given: the config's text, not this machine's folders (docs/transfer.md)
        json["kb"] = {{"file", kb_file_given}};
    } else {
        json["kb"] = {{"from", kb_from == KbFrom::merge ? "merge" : "best"}};
    }
    if (kb_delta) json["kb"]["delta"] = *kb_delta;
    json["randomize_seed"] = randomize_seed;
    if (seed) {
        // as kb.file: the file as given, not this machine's folders
        json["seed"] =
            seed->from_file ? nlohmann::json{{"file", seed->file_given}} : nlohmann::json{{"from", "best"}};
        json["seed"]["with"] = to_string(seed->with);
        if (seed->count) json["seed"]["count"] = *seed->count;
    }
    json["target"] = step_json(target);
    auto names = nlohmann::json::array();
    for (Treatment t : treatments) names.push_back(to_string(t));
    json["target"]["treatments"] = names;
    return json;
}

bool CampaignConfig::needs_kb() const {
    return std::any_of(treatments.begin(), treatments.end(), runs::needs_kb);
}

bool CampaignConfig::needs_randomized_kb() const {
    return std::any_of(treatments.begin(), treatments.end(), runs::needs_randomized_kb);
}

bool CampaignConfig::seeded() const {
    return std::any_of(treatments.begin(), treatments.end(), runs::is_seeded);
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

void write_step_config(const fs::path& path, const RunStep& step) {
    nlohmann::json json = step.config.to_file_json();  // read back as a user config: math named
    json["ea"]["generations"] = step.generations;
    OutputFile out(path, true);
    out.stream() << json.dump(2) << "\n";
    out.commit();
}

}  // namespace stepstone::runs
