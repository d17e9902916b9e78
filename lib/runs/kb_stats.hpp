#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "kb/knowledge_base.hpp"

namespace stepstone::runs {

// The figures behind `stepstone kb stats` (apps/ formats them).

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
    std::size_t zero_average = 0;  ///< segments whose average reward is exactly 0
    std::string digest;            ///< content digest (db::kb_digest), filled by kb_file_stats
    std::vector<kb::Source> sources;
    double bytes_per_segment = 0.0;       ///< in memory (values, record, index)
    double file_bytes_per_segment = 0.0;  ///< of the file, 0 for an empty KB
};

/// Statistics of a loaded KB (file, name and file_bytes_per_segment left empty).
KbStats compute_kb_stats(const kb::KnowledgeBase& kb, std::size_t bins = 10);
/// Loads the KB (the only one, or `name`) of `kb_db` and computes its statistics.
KbStats kb_file_stats(const std::filesystem::path& kb_db, const std::string& name = "");

}  // namespace stepstone::runs
