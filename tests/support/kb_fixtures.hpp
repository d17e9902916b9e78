#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "kb/knowledge_base.hpp"

namespace stepstone::kbtest {

/// Segment width of the tiny run's KB (its config), chosen unlike the
/// default 20 so a test sees where a command took the width from.
inline constexpr std::size_t kRunWidth = 10;
/// Steps of the tiny run's only start.
inline constexpr std::size_t kRunSteps = 200;

/// Runs `stepstone evolve` on a tiny source config (population 8, 3
/// generations, one start of 200 steps, a KB of width 10 and delta 1 observed
/// every generation, seed 3) into `path`; `retain_all` keeps every genome.
void make_run(const std::filesystem::path& path, bool retain_all = false);

/// Writes `kb` as the only KB of a new database file.
void write_kb(const std::filesystem::path& path, const std::string& name, const kb::KnowledgeBase& kb,
              std::optional<std::uint64_t> randomized_seed = std::nullopt);

/// Loads the only KB of a file (or `name`).
kb::KnowledgeBase load_kb(const std::filesystem::path& path, const std::string& name = "");

/// A 1-step, 2-channel KB (delta 0.5) fed one segment per policy:
/// `policies` = {x, y, reward, generation}, all from source `run`.
struct Policy {
    float x = 0;
    float y = 0;
    double reward = 0;
    std::int64_t generation = 0;
};
kb::KnowledgeBase point_kb(const std::string& run, const std::vector<Policy>& policies, double delta = 0.5,
                           std::size_t channels = 2);

/// Eight 1-value segments (width 1, one channel, delta 0.5) with averages
/// 0, 0, 0, 0.15, 0.55, 0.55, 0.95, 1.0 and counts 1, 2, 3, 1, 4, 1, 1, 2;
/// sources alpha (generations 0-10, 30 policies) and beta (5-7, 4); first
/// origins: ids 0-2 alpha generation 0, ids 3-5 alpha generation 3, ids 6-7
/// beta generation 5; segment 0 was last credited by beta at generation 7.
kb::KnowledgeBase histogram_kb();

/// The kb_segment rows of a file as text, in id order (every column), to
/// compare two files' segments exactly.
std::vector<std::string> segment_rows(const std::filesystem::path& path);

/// Names of the files of a directory (to check that nothing was left behind),
/// without the -wal and -shm files that SQLite readers of a WAL database
/// leave beside it.
std::vector<std::string> files_in(const std::filesystem::path& dir);

}  // namespace stepstone::kbtest
