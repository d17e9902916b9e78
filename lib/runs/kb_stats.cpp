#include "runs/kb_stats.hpp"

#include <algorithm>
#include <cmath>

#include "db/digest.hpp"
#include "runs/kb_files.hpp"
#include "stats/summary.hpp"

namespace stepstone::runs {

namespace fs = std::filesystem;

KbStats compute_kb_stats(const kb::KnowledgeBase& kb, std::size_t bins) {
    KbStats stats;
    stats.params = kb.params();
    stats.segments = kb.size();
    stats.max_average = kb.max_average();
    stats.sources.assign(kb.sources().begin(), kb.sources().end());
    stats.bytes_per_segment = kb.bytes_per_segment();

    // histogram of the averages over [0, max] ([0, 1] when every average is 0)
    const double top = stats.max_average > 0 ? stats.max_average : 1.0;
    for (std::size_t b = 0; b < bins; ++b) {
        stats.histogram.push_back({top * static_cast<double>(b) / static_cast<double>(bins),
                                   top * static_cast<double>(b + 1) / static_cast<double>(bins), 0});
    }
    std::vector<double> counts;
    counts.reserve(kb.size());
    for (const auto& record : kb.records()) {
        const double scaled = std::floor(record.average() / top * static_cast<double>(bins));
        const std::size_t bin = scaled <= 0 ? 0 : std::min(bins - 1, static_cast<std::size_t>(scaled));
        if (bins > 0) ++stats.histogram[bin].segments;
        counts.push_back(static_cast<double>(record.count));
        stats.observations += record.count;
        if (record.count == 1) ++stats.count_one;
        if (record.cum_reward == 0.0) ++stats.zero_average;
    }
    if (!counts.empty()) {
        const auto records = kb.records();
        const auto [low, high] = std::minmax_element(
            records.begin(), records.end(), [](const auto& a, const auto& b) { return a.count < b.count; });
        stats.count_min = low->count;
        stats.count_max = high->count;
        stats.count_mean = static_cast<double>(stats.observations) / static_cast<double>(counts.size());
        stats.count_median = stats::median(counts);
    }
    return stats;
}

KbStats kb_file_stats(const fs::path& kb_db, const std::string& name) {
    const auto stored = load_kb_file(kb_db, name);
    KbStats stats = compute_kb_stats(stored.kb);
    stats.file = kb_db.string();
    stats.name = stored.name;
    stats.randomized_seed = stored.randomized_seed;
    stats.digest = db::kb_digest(stored.kb, stored.randomized_seed);
    if (stats.segments > 0) {
        stats.file_bytes_per_segment =
            static_cast<double>(fs::file_size(kb_db)) / static_cast<double>(stats.segments);
    }
    return stats;
}

}  // namespace stepstone::runs
