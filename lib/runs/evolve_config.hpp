#pragma once

#include <cstdint>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "kb/knowledge_base.hpp"
#include "nn/dnn_config.hpp"
#include "runs/treatment.hpp"
#include "sim/task.hpp"

namespace stepstone::runs {

/// The largest seed a config accepts (seeds are stored as SQLite integers).
inline constexpr std::int64_t kMaxSeed = std::numeric_limits<std::int64_t>::max();

/// NSGA-II settings (docs/original.md: NSGA-II). Defaults are the paper's.
struct EaConfig {
    /// mu = lambda; a positive multiple of 4 (the tournament works in blocks of 4).
    int population_size = 200;
    /// Epochs after generation 0 (the random start): 4000 gives sferes2's
    /// nb_gen = 4001 generations, numbered 0 to 4000.
    int generations = 4000;
    /// Generation 0 evaluates initial_multiplier x population_size random
    /// genomes and keeps population_size (sferes2 initial_aleat = 2).
    int initial_multiplier = 2;
};

/// The knowledge base a run builds from its own policies (the paper's
/// section II.B). Defaults are the paper's.
struct KbConfig {
    int segment_width = static_cast<int>(kb::kDefaultSegmentWidth);  ///< time steps per segment
    double delta = 1.83;                 ///< a segment closer than delta to a KB segment credits it
    int period = 200;                    ///< observe every `period` generations (1 = every generation)
    std::string match = "within_delta";  ///< lookup rule: within_delta | nearest
    std::string counting = "occurrence";  ///< observe's credit rule: occurrence | policy (kb::Counting)
};

/// Which policies of a source run seed a target run's generation 0
/// (docs/transfer.md: seeding).
enum class SeedWith {
    population,  ///< the latest checkpoint's population (the parents a resume would start from)
    front,       ///< its first front (non-dominated under the objectives stored with them)
    best,        ///< the stored genomes with the highest task reward
};

/// "population", "front" or "best".
std::string_view to_string(SeedWith with);
/// Parses a SeedWith name; throws ConfigError naming `what` and the accepted names otherwise.
SeedWith parse_seed_with(const std::string& text, const std::string& what);

/// A run's seeding: generation 0 starts from policies of a finished source
/// run (transfer.seed).
struct SeedConfig {
    /// The source run file. In a config file a relative path is relative to
    /// the config file's folder; on the command line, to the working directory.
    std::filesystem::path from;
    SeedWith with = SeedWith::population;
    /// At most this many policies, the first by task reward (highest first,
    /// lower source individual id on ties); 0 (absent): ea.population_size.
    int count = 0;
    std::string digest;  ///< the source run's db::run_digest, filled when the run starts and stored
};

/// The knowledge base that shapes a run's reward and how (the paper's
/// treatments, section III.D), and the source run that seeds it.
struct TransferConfig {
    /// The shaping: one of the paper's five (never a seeded name: the seed says that).
    Treatment treatment = Treatment::none;
    /// The KB file. In a config file a relative path is relative to the
    /// config file's folder; on the command line, to the working directory.
    std::filesystem::path kb;
    std::string kb_name;    ///< the KB in that file; empty: the file's only one
    std::string kb_digest;  ///< content digest of the KB used, filled when the run starts and stored
    std::optional<SeedConfig> seed;  ///< absent: generation 0 is random
};

/// Which genomes a run stores for replay.
enum class Retain {
    front,  ///< the first front and the best of every generation
    all,    ///< every evaluated genome
};

/// Where a config's JSON comes from, which decides what an absent "math" means.
enum class ConfigOrigin {
    user,    ///< a config file or campaign step written by a user: absent means portable
    stored,  ///< a run's stored config (EvolveConfig::to_json): absent means libm
};

/// The math a stored config (EvolveConfig::to_json) holds: its "math", libm when
/// absent or when `stored` is not an object; nullopt for a name that is not a Math.
std::optional<Math> stored_math(const nlohmann::json& stored);

/// Everything `stepstone evolve` reads from its config file.
struct EvolveConfig {
    sim::TaskConfig task;
    nn::DnnConfig dnn;
    EaConfig ea;
    std::optional<std::uint64_t> seed;  ///< absent: drawn from the OS and stored
    Retain retain = Retain::front;
    std::optional<KbConfig> kb;              ///< absent: the run builds no knowledge base
    std::optional<TransferConfig> transfer;  ///< absent: no shaping (treatment none)

    /// The JSON named "math" (false: the origin's default was taken; a user
    /// config that resumes a run then inherits the run's math).
    bool math_given = false;

    /// The run's shaping treatment (none without a transfer block).
    Treatment treatment() const { return transfer ? transfer->treatment : Treatment::none; }
    /// The run's seeding, null when generation 0 is random.
    const SeedConfig* seeding() const { return transfer && transfer->seed ? &*transfer->seed : nullptr; }
    /// The treatment a run file records (`run.treatment`): the shaping
    /// treatment, or its seeded twin (seed-sum, ...) when the run is seeded.
    Treatment run_treatment() const { return seeding() ? seeded(treatment()) : treatment(); }
    /// The sine, cosine and power of the run (the JSON's "math"): the task's and
    /// the mutation's, kept equal. Absent from a user config: "portable"; absent
    /// from a stored config: "libm" (to_json() leaves libm out, as every run file
    /// made before portable became the default holds it).
    Math math() const { return task.math; }
    void set_math(Math math) {
        task.math = math;
        dnn.math = math;
    }

    /// Strict parse: unknown keys, wrong types and out-of-range values throw
    /// ConfigError naming `source` and the key path. Keys: task {kind,
    /// steps_per_start, starts, still_limit, grid_period}, ea {population_size,
    /// generations, initial_multiplier}, dnn {see nn::DnnConfig}, kb
    /// {segment_width, delta, period, match}, transfer {treatment, kb,
    /// kb_name, kb_digest, seed {from, with, count, digest}}, seed, retain.
    /// task.arena names an arena file (relative to `folder`, else to the working
    /// directory) or holds the arena itself (sim::ArenaSpec::from_json).
    static EvolveConfig from_json(const nlohmann::json& json, const std::string& source = "config",
                                  const std::filesystem::path& folder = {},
                                  ConfigOrigin origin = ConfigOrigin::user);
    /// Reads and parses a config file; a relative transfer.kb,
    /// transfer.seed.from or task.arena is taken relative to the file's folder.
    static EvolveConfig load(const std::filesystem::path& path);

    /// The effective config as stored with the run: every key with its value,
    /// the seed included, `ea.generations` excluded (it is the run's own
    /// column, so a run can be extended on resume).
    /// "math" is written only when portable, so that the stored configs of
    /// libm runs are what they were before the key existed (digests included):
    /// read it back with ConfigOrigin::stored.
    nlohmann::json to_json() const;
    /// to_json() with "math" always written: a config file that another
    /// process reads as a user config (a campaign's step configs).
    nlohmann::json to_file_json() const;
};

}  // namespace stepstone::runs
