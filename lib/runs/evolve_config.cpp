#include "runs/evolve_config.hpp"

#include "core/config.hpp"
#include "core/error.hpp"
#include "core/text.hpp"

namespace stepstone::runs {

namespace {

// task.arena: a file name (relative to `folder`) or the arena itself, inline (as a run stores it)
std::shared_ptr<const sim::ArenaSpec> read_arena(JsonReader& reader, const std::filesystem::path& folder) {
    const nlohmann::json& raw = reader.raw("arena");
    if (raw.is_null()) return nullptr;
    if (raw.is_string()) {
        std::filesystem::path file = raw.get<std::string>();
        if (file.is_relative() && !folder.empty()) file = folder / file;
        return std::make_shared<const sim::ArenaSpec>(sim::ArenaSpec::load(file));
    }
    if (!raw.is_object()) {
        throw ConfigError(
            concat(reader.path_of("arena"), " must be an arena file's name or an arena object"));
    }
    return std::make_shared<const sim::ArenaSpec>(sim::ArenaSpec::from_json(raw, reader.path_of("arena")));
}

sim::TaskConfig read_task(JsonReader reader, const std::filesystem::path& folder) {
    sim::TaskConfig task;
    task.arena = read_arena(reader, folder);
    std::string kind(sim::to_string(task.kind));
    reader.read_choice("kind", kind, {"source", "target"});
    task.kind = sim::parse_task_kind(kind, reader.path_of("kind"));
    reader.read("steps_per_start", task.steps_per_start, 1, 1000000);
    reader.read("starts", task.starts, 1, 3);
    reader.read("still_limit", task.still_limit, 0, 100000000);
    reader.read("grid_period", task.grid_period, 1, 1000000);
    reader.finish();
    task.validate();
    return task;
}

EaConfig read_ea(JsonReader reader) {
    EaConfig ea;
    reader.read("population_size", ea.population_size, 4, 1000000);
    if (ea.population_size % 4 != 0) {
        throw ConfigError(
            concat(reader.path_of("population_size"), " must be a multiple of 4, got ", ea.population_size));
    }
    reader.read("generations", ea.generations, 0, 100000000);
    reader.read("initial_multiplier", ea.initial_multiplier, 1, 100);
    reader.finish();
    return ea;
}

KbConfig read_kb(JsonReader reader) {
    KbConfig kb;
    reader.read("segment_width", kb.segment_width, 1, 1000000);
    reader.read("delta", kb.delta, -1e300, 1e300);
    if (kb.delta <= 0) throw ConfigError(concat(reader.path_of("delta"), " must be > 0, got ", kb.delta));
    reader.read("period", kb.period, 1, 100000000);
    reader.read_choice("match", kb.match, {"within_delta", "nearest"});
    reader.read_choice("counting", kb.counting, {"occurrence", "policy"});
    reader.finish();
    return kb;
}

SeedConfig read_seed(JsonReader reader) {
    SeedConfig seed;
    std::string from;
    reader.read("from", from);
    if (from.empty()) throw ConfigError(concat(reader.path_of("from"), " is required (the source run file)"));
    seed.from = from;
    std::string with(to_string(seed.with));
    reader.read_choice("with", with, {"population", "front", "best"});
    seed.with = parse_seed_with(with, reader.path_of("with"));
    if (reader.has("count")) {
        seed.count = -1;
        reader.read("count", seed.count, -1000000000, 1000000000);
        if (seed.count <= 0)
            throw ConfigError(concat(reader.path_of("count"), " must be >= 1, got ", seed.count));
    }
    reader.read("digest", seed.digest);
    reader.finish();
    return seed;
}

TransferConfig read_transfer(JsonReader reader) {
    TransferConfig transfer;
    std::string treatment = "none";
    reader.read("treatment", treatment);
    transfer.treatment = parse_shaping_treatment(treatment, reader.path_of("treatment"));
    std::string kb;
    reader.read("kb", kb);
    transfer.kb = kb;
    reader.read("kb_name", transfer.kb_name);
    reader.read("kb_digest", transfer.kb_digest);
    if (reader.has("seed")) transfer.seed = read_seed(reader.child("seed"));
    reader.finish();
    if (needs_kb(transfer.treatment) && transfer.kb.empty()) {
        throw ConfigError(concat(reader.path_of("kb"), " is required by treatment ", treatment));
    }
    return transfer;
}

}  // namespace

std::string_view to_string(SeedWith with) {
    switch (with) {
        case SeedWith::population:
            return "population";
        case SeedWith::front:
            return "front";
        case SeedWith::best:
            return "best";
    }
    return "population";
}

SeedWith parse_seed_with(const std::string& text, const std::string& what) {
    for (SeedWith with : {SeedWith::population, SeedWith::front, SeedWith::best}) {
        if (text == to_string(with)) return with;
    }
    throw ConfigError(concat(what, " must be one of population, front, best, got \"", text, "\""));
}

std::optional<Math> stored_math(const nlohmann::json& stored) {
    if (!stored.is_object() || !stored.contains("math")) return Math::libm;
    return stored["math"].is_string() ? parse_math(stored["math"].get<std::string>()) : std::nullopt;
}

EvolveConfig EvolveConfig::from_json(const nlohmann::json& json, const std::string& source,
                                     const std::filesystem::path& folder, ConfigOrigin origin) {
    try {
        JsonReader root(json, "");
        EvolveConfig config;
        config.task = read_task(root.child("task"), folder);
        config.ea = read_ea(root.child("ea"));
        auto dnn = root.child("dnn");
        config.dnn = nn::DnnConfig::from_json(dnn);
        if (config.dnn.inputs != sim::kInputs || config.dnn.outputs != sim::kOutputs) {
            throw ConfigError(concat("dnn.inputs and dnn.outputs must be ", sim::kInputs, " and ",
                                     sim::kOutputs, " for the robot, got ", config.dnn.inputs, " and ",
                                     config.dnn.outputs));
        }
        if (root.has("seed")) {
            std::int64_t seed = 0;
            root.read("seed", seed, 0, kMaxSeed);
            config.seed = static_cast<std::uint64_t>(seed);
        }
        if (root.has("kb")) {
            config.kb = read_kb(root.child("kb"));
            if (config.kb->segment_width > config.task.steps_per_start) {
                throw ConfigError(concat("kb.segment_width must be <= task.steps_per_start (",
                                         config.task.steps_per_start, "), got ", config.kb->segment_width));
            }
        }
        if (root.has("transfer")) config.transfer = read_transfer(root.child("transfer"));
        // no count: the whole population, as many as generation 0 keeps
        if (config.transfer && config.transfer->seed && config.transfer->seed->count == 0) {
            config.transfer->seed->count = config.ea.population_size;
        }
        std::string retain = "front";
        root.read_choice("retain", retain, {"front", "all"});
        config.retain = retain == "all" ? Retain::all : Retain::front;
        config.math_given = root.has("math");
        std::string math(to_string(origin == ConfigOrigin::stored ? Math::libm : Math::portable));
        root.read_choice("math", math, {"libm", "portable"});
        config.set_math(*parse_math(math));  // read_choice allowed only the two names
        root.finish();
        return config;
    } catch (const ConfigError& e) {
        throw ConfigError(concat(source, ": ", e.what()));
    }
}

EvolveConfig EvolveConfig::load(const std::filesystem::path& path) {
    const nlohmann::json json = load_json_file(path);
    if (json.is_object() && json.contains("target") && !json.contains("task")) {
        throw ConfigError(
            concat(path.string(), ": this is a campaign config, not a run config (run it as a campaign)"));
    }
    EvolveConfig config = from_json(json, path.string(), path.parent_path());
    if (config.transfer && !config.transfer->kb.empty() && config.transfer->kb.is_relative()) {
        config.transfer->kb = path.parent_path() / config.transfer->kb;
    }
    if (config.transfer && config.transfer->seed && config.transfer->seed->from.is_relative()) {
        config.transfer->seed->from = path.parent_path() / config.transfer->seed->from;
    }
    return config;
}

nlohmann::json EvolveConfig::to_json() const {
    nlohmann::json json;
    json["task"] = {{"kind", sim::to_string(task.kind)},
                    {"steps_per_start", task.steps_per_start},
                    {"starts", task.starts},
                    {"still_limit", task.still_limit},
                    {"grid_period", task.grid_period}};
    // a run stores its arena whole, so that it replays without the file; the paper's is the default
    if (task.arena) json["task"]["arena"] = task.arena->to_json();
    json["ea"] = {{"population_size", ea.population_size}, {"initial_multiplier", ea.initial_multiplier}};
    json["dnn"] = {{"inputs", dnn.inputs},
                   {"outputs", dnn.outputs},
                   {"weight_min", dnn.weight_min},
                   {"weight_max", dnn.weight_max},
                   {"bias_min", dnn.bias_min},
                   {"bias_max", dnn.bias_max},
                   {"bias_scale", dnn.bias_scale},
                   {"parameter_mutation_rate", dnn.parameter_mutation_rate},
                   {"polynomial_eta", dnn.polynomial_eta},
                   {"rewire_connection_rate", dnn.rewire_connection_rate},
                   {"add_connection_rate", dnn.add_connection_rate},
                   {"delete_connection_rate", dnn.delete_connection_rate},
                   {"add_neuron_rate", dnn.add_neuron_rate},
                   {"delete_neuron_rate", dnn.delete_neuron_rate}};
    if (seed) json["seed"] = *seed;
    json["retain"] = retain == Retain::all ? "all" : "front";
    // written only when not the default, so that the configs stored before the key existed compare equal
    if (math() == Math::portable) json["math"] = to_string(Math::portable);
    if (kb) {
        json["kb"] = {{"segment_width", kb->segment_width},
                      {"delta", kb->delta},
                      {"period", kb->period},
                      {"match", kb->match}};
        // as math: only when not the default, so that older stored configs compare equal
        if (kb->counting != "occurrence") json["kb"]["counting"] = kb->counting;
    }
    if (transfer) {
        json["transfer"] = {{"treatment", to_string(transfer->treatment)}};
        // a seeded run without a KB names none; every other transfer block as before seeding existed
        if (!transfer->kb.empty() || !transfer->seed) {
            json["transfer"]["kb"] = transfer->kb.string();
            json["transfer"]["kb_name"] = transfer->kb_name;
        }
        if (!transfer->kb_digest.empty()) json["transfer"]["kb_digest"] = transfer->kb_digest;
        if (transfer->seed) {
            const SeedConfig& seeding = *transfer->seed;
            json["transfer"]["seed"] = {
                {"from", seeding.from.string()}, {"with", to_string(seeding.with)}, {"count", seeding.count}};
            if (!seeding.digest.empty()) json["transfer"]["seed"]["digest"] = seeding.digest;
        }
    }
    return json;
}

nlohmann::json EvolveConfig::to_file_json() const {
    nlohmann::json json = to_json();
    json["math"] = to_string(math());
    return json;
}

}  // namespace stepstone::runs
