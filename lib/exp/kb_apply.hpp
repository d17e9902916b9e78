#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "kb/knowledge_base.hpp"

namespace stepstone::exp {

// The work behind `stepstone kb annotate` and `stepstone shape`: a KB applied
// to a run's stored policies. The KB file is opened read-only; `annotate`
// writes into the run file, in one transaction, under its writer lock.

/// Which stored policies `kb annotate` replays.
enum class PolicySet {
    best,   ///< the stored genome with the highest reward (lowest id on ties)
    front,  ///< the first front of the run's last checkpointed population
    all,    ///< every stored genome
};
/// "best", "front" or "all"; throws ConfigError naming `what` (the caller's
/// name for the choice) otherwise.
PolicySet parse_policy_set(const std::string& text, const std::string& what);

/// What `kb annotate` did.
struct Annotation {
    std::string kb_name;                    ///< the KB's name in the run file
    std::int64_t kb_id = 0;                 ///< its id in the run file (policy_segment.kb_id)
    bool copied = false;                    ///< true if the KB was copied into the run file
    std::vector<std::int64_t> individuals;  ///< annotated, in id order
    std::size_t rows = 0;                   ///< policy_segment rows written
};

/// The run file already holds a different KB under the name asked for; what()
/// names the file and the KB. The caller may offer a way to choose another.
class KbNameTaken : public DataError {
public:
    using DataError::DataError;
};

/// Replays the `which` policies of `run_db` and writes, for each of their
/// segments, its match in the KB of `kb_db` (the only one, or `kb_name`)
/// into policy_segment. policy_segment.kb_id refers to a KB of the run file
/// itself, so saliency queries join within one file: the KB is copied into
/// the run file under `as_name` (empty: its own name) unless an identical KB
/// (same parameters, segments and statistics) already has that name; a
/// different KB of that name is refused (KbNameTaken). Everything is written
/// in one transaction, after every replay succeeded. Throws DataError when
/// the KB's channels differ from the behaviour's or its width exceeds it.
Annotation annotate_run(const std::filesystem::path& run_db, const std::filesystem::path& kb_db,
                        PolicySet which, const std::string& kb_name = "", const std::string& as_name = "");

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

}  // namespace stepstone::exp
