#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>

#include "db/kb_store.hpp"
#include "kb/knowledge_base.hpp"

namespace stepstone::runs {

// The work behind `stepstone kb export | merge | randomize`: KB files in, one
// KB file out. Inputs are opened read-only; the output is written under a
// temporary name and renamed when complete (db::OutputDatabase), and an
// existing output is refused (ConfigError) unless `force`.

/// What a command wrote into a KB file.
struct KbWritten {
    std::string name;                              ///< the KB's name in the output
    kb::KbParams params;                           ///< its shape and rule
    std::size_t segments = 0;                      ///< its size
    std::optional<std::uint64_t> randomized_seed;  ///< set for a randomized KB
    double max_average = 0.0;                      ///< its largest average reward (0 if empty)
};

/// Writes `kb` under `name` as the only content of a new KB file `out`,
/// atomically (written under a temporary name, then renamed). Throws
/// ConfigError for an existing output without `force`, a folder, or a
/// missing parent folder; DataError for an unusable name.
void save_kb_file(const std::filesystem::path& out, bool force, const std::string& name,
                  const kb::KnowledgeBase& kb, std::optional<std::uint64_t> randomized_seed = std::nullopt);

/// Loads the KB called `name` (empty: the only one) of the file at `path`,
/// opened read-only.
db::StoredKb load_kb_file(const std::filesystem::path& path, const std::string& name);

/// `kb export`: copies the KB called `name` of `run_db` (parameters, sources,
/// segments, randomized seed) into a new file `out`, named `out_name` (empty:
/// the same name).
/// Throws DataError if the run file has no such KB, DatabaseError for an
/// unusable file, ConfigError for an existing output without `force`.
/// With `delta`, the KB written is kb::KnowledgeBase::coarsened(delta) (a
/// smaller KB: ConfigError for a delta below the run's, DataError for a
/// randomized KB).
KbWritten export_kb(const std::filesystem::path& run_db, const std::string& name,
                    const std::filesystem::path& out, bool force, std::optional<double> delta = std::nullopt,
                    const std::string& out_name = "");

/// `kb merge`: loads the only KB of each input (or the one called
/// `input_name` when given) and merges every later one into the first, in
/// the given order (kb::KnowledgeBase::merge: observed under the first's
/// delta, cumulated rewards and counts added, sources appended). The result
/// is stored under `name` (empty: the first KB's name). Throws DataError
/// naming both files and values when segment width, channels or delta
/// differ, ConfigError for fewer than two inputs and, unless
/// `allow_duplicates`, DuplicateKbs for two inputs that are the same file,
/// hold the same KB or share a source run (its policies would count twice);
/// no output is left then.
KbWritten merge_kb_files(std::span<const std::filesystem::path> inputs, const std::filesystem::path& out,
                         const std::string& name, bool force, const std::string& input_name = "",
                         bool allow_duplicates = false);

/// `kb randomize`: the KB of `in` with averages drawn from U[0, 1)
/// (kb::KnowledgeBase::randomized(seed)), stored with its randomized_seed
/// under `name` (empty: the input's name followed by "-rand").
KbWritten randomize_kb_file(const std::filesystem::path& in, const std::filesystem::path& out,
                            std::uint64_t seed, const std::string& name, bool force,
                            const std::string& input_name = "");

}  // namespace stepstone::runs
