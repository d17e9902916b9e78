#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <ostream>
#include <span>
#include <string>
#include <vector>

#include "core/progress.hpp"
#include "kb/calibrate.hpp"
#include "kb/knowledge_base.hpp"

namespace stepstone::exp {

// The work behind `stepstone kb ...` and `stepstone shape`. Inputs are opened
// read-only (except the run file that `annotate` fills); new files are written
// under a temporary name and renamed when complete (db::OutputDatabase), and
// an existing output is refused (ConfigError) unless `force`.

/// The name evolve gives the knowledge base it stores in a run file.
inline constexpr const char* kRunKbName = "run";

/// What a command wrote into a KB file.
struct KbWritten {
    std::string name;                              ///< the KB's name in the output
    kb::KbParams params;                           ///< its shape and rule
    std::size_t segments = 0;                      ///< its size
    std::optional<std::uint64_t> randomized_seed;  ///< set for a randomized KB
};

/// `kb export`: copies the KB called `name` of `run_db` (parameters, sources,
/// segments, randomized seed) into a new file `out` under the same name.
/// Throws DataError if the run file has no such KB, DatabaseError for an
/// unusable file, ConfigError for an existing output without `force`.
/// With `delta`, the KB written is kb::KnowledgeBase::coarsened(delta) (a
/// smaller KB: ConfigError for a delta below the run's, DataError for a
/// randomized KB).
KbWritten export_kb(const std::filesystem::path& run_db, const std::string& name,
                    const std::filesystem::path& out, bool force, std::optional<double> delta = std::nullopt);

/// `kb merge`: loads the only KB of each input (or the one called
/// `input_name` when given) and merges every later one into the first, in
/// the given order (kb::KnowledgeBase::merge: observed under the first's
/// delta, cumulated rewards and counts added, sources appended). The result
/// is stored under `name` (empty: the first KB's name). Throws DataError
/// naming both files and values when segment width, channels or delta
/// differ, ConfigError for fewer than two inputs and, unless
/// `allow_duplicates`, for two inputs that are the same file, hold the same
/// KB or share a source run (its policies would count twice); no output is
/// left then.
KbWritten merge_kb_files(std::span<const std::filesystem::path> inputs, const std::filesystem::path& out,
                         const std::string& name, bool force, const std::string& input_name = "",
                         bool allow_duplicates = false);

/// `kb randomize`: the KB of `in` with averages drawn from U[0, 1)
/// (kb::KnowledgeBase::randomized(seed)), stored with its randomized_seed
/// under `name` (empty: the input's name followed by "-rand").
KbWritten randomize_kb_file(const std::filesystem::path& in, const std::filesystem::path& out,
                            std::uint64_t seed, const std::string& name, bool force,
                            const std::string& input_name = "");

// ---------------------------------------------------------------- calibrate

/// The delta rule and the KB size table computed from behaviours.
struct Calibration {
    std::size_t segment_width = 0;     ///< steps per segment used
    std::size_t channels = 0;          ///< channels of the behaviours
    std::size_t neighbours = 20;       ///< the "20 closest" of the rule
    std::size_t segments = 0;          ///< segments of the calibrating policy
    double delta = 0.0;                ///< kb::calibrate_delta on the calibrating policy
    std::size_t policies = 0;          ///< policies fed to the size table
    std::vector<kb::DeltaSize> sizes;  ///< KB size per delta, in the order asked
};

/// The paper's delta rule on `policy` (a behaviour matrix: rows = steps,
/// `channels` columns) and, for each of `deltas`, the size of a KB fed with
/// `policies` in order. Throws DataError for bad behaviours (too few
/// segments, NaN) and ConfigError for a delta <= 0.
Calibration calibrate_behaviours(std::span<const float> policy, std::span<const std::vector<float>> policies,
                                 std::size_t channels, std::size_t segment_width,
                                 std::span<const double> deltas, std::size_t neighbours = 20);

/// What `kb calibrate` reads from a run file.
struct CalibrateOptions {
    std::string individual = "best";           ///< the successful policy: "best" or an id
    std::optional<std::size_t> segment_width;  ///< absent: the run KB's, else 20
    std::vector<double> deltas;                ///< the size table's deltas (empty: no table)
    std::size_t neighbours = 20;
    unsigned threads = 0;                      ///< replays and KBs at once (0 = every core)
    std::size_t batch = 256;                   ///< policies replayed per batch (bounds memory)
    ProgressMode progress = ProgressMode::quiet;  ///< policies replayed, on stderr
};

/// calibrate_behaviours on a run: the replayed behaviour of `individual` and
/// of every stored genome (in individual id order). The genomes are replayed
/// `batch` at a time on `threads` threads (first start only: the behaviour
/// is the first start's), then each batch is observed, in id order, into one
/// KB per delta, the KBs side by side on the same threads; the sizes do not
/// depend on `threads` or `batch`.
struct RunCalibration {
    std::int64_t individual_id = 0;  ///< the calibrating policy
    double reward = 0.0;             ///< its stored reward
    std::string width_from;          ///< "--segment-width", "the run's knowledge base" or "default"
    Calibration calibration;
};
RunCalibration calibrate_run(const std::filesystem::path& run_db, const CalibrateOptions& options);

/// Parses "0.5,1,1.83" into deltas; throws ConfigError naming `what` for an
/// empty item, a non-number or a value that is not finite and > 0.
std::vector<double> parse_deltas(const std::string& text, const std::string& what = "--deltas");

// -------------------------------------------------------------------- stats

/// One bin of the average-reward histogram.
struct RewardBin {
    double low = 0.0;   ///< inclusive
    double high = 0.0;  ///< exclusive, except for the last bin
    std::size_t segments = 0;
};

/// Summary of a KB (`kb stats`).
struct KbStats {
    std::string file;
    std::string name;
    kb::KbParams params;
    std::optional<std::uint64_t> randomized_seed;
    std::size_t segments = 0;
    double max_average = 0.0;
    /// 10 bins of width max_average / 10 over [0, max_average]; a segment
    /// falls in bin floor(10 * average / max_average), the maximum in the
    /// last; negative averages count in the first. When max_average <= 0
    /// the bins cover [0, 1] instead.
    std::vector<RewardBin> histogram;
    std::uint64_t observations = 0;  ///< sum of the counts
    std::uint64_t count_min = 0, count_max = 0;
    double count_mean = 0.0, count_median = 0.0;
    std::size_t count_one = 0;  ///< segments seen once
    std::vector<kb::Source> sources;
    double bytes_per_segment = 0.0;       ///< in memory (values, record, index)
    double file_bytes_per_segment = 0.0;  ///< of the file, 0 for an empty KB
};

/// Statistics of a loaded KB (file, name and file_bytes_per_segment left empty).
KbStats compute_kb_stats(const kb::KnowledgeBase& kb, std::size_t bins = 10);
/// Loads the KB (the only one, or `name`) of `kb_db` and computes its statistics.
KbStats kb_file_stats(const std::filesystem::path& kb_db, const std::string& name = "");
nlohmann::json to_json(const KbStats& stats);
/// The text report: parameters, the histogram with a bar of '#', counts, provenance.
void write_text(std::ostream& out, const KbStats& stats);

// ----------------------------------------------------------------- annotate

/// Which stored policies `kb annotate` replays.
enum class PolicySet {
    best,   ///< the stored genome with the highest reward (lowest id on ties)
    front,  ///< the first front of the run's last checkpointed population
    all,    ///< every stored genome
};
/// "best", "front" or "all"; throws ConfigError otherwise.
PolicySet parse_policy_set(const std::string& text);

/// What `kb annotate` did.
struct Annotation {
    std::string kb_name;                    ///< the KB's name in the run file
    std::int64_t kb_id = 0;                 ///< its id in the run file (policy_segment.kb_id)
    bool copied = false;                    ///< true if the KB was copied into the run file
    std::vector<std::int64_t> individuals;  ///< annotated, in id order
    std::size_t rows = 0;                   ///< policy_segment rows written
};

/// Replays the `which` policies of `run_db` and writes, for each of their
/// segments, its match in the KB of `kb_db` (the only one, or `kb_name`)
/// into policy_segment. policy_segment.kb_id refers to a KB of the run file
/// itself, so saliency queries join within one file: the KB is copied into
/// the run file under `as_name` (empty: its own name) unless an identical KB
/// (same parameters, segments and statistics) already has that name; a
/// different KB of that name is refused (DataError). Everything is written
/// in one transaction, after every replay succeeded. Throws DataError when
/// the KB's channels differ from the behaviour's or its width exceeds it.
Annotation annotate_run(const std::filesystem::path& run_db, const std::filesystem::path& kb_db,
                        PolicySet which, const std::string& kb_name = "", const std::string& as_name = "");

// -------------------------------------------------------------------- shape

/// r_max and the per-segment matches of one stored policy (`stepstone shape`).
struct Shaping {
    std::int64_t individual_id = 0;
    int generation = 0;
    double stored_reward = 0.0;
    std::string kb_name;
    kb::KbParams params;
    double max_average = 0.0;  ///< the KB's largest average (the sum treatment's normaliser)
    double r_max = 0.0;
    std::vector<kb::SegmentMatch> segments;  ///< segment i covers steps [i w, (i + 1) w)
};
Shaping shape_policy(const std::filesystem::path& kb_db, const std::filesystem::path& run_db,
                     const std::string& individual, const std::string& kb_name = "");
nlohmann::json to_json(const Shaping& shaping);
void write_text(std::ostream& out, const Shaping& shaping);

}  // namespace stepstone::exp
