#pragma once

// Small databases built by the report tests with the real binary.

#include <filesystem>
#include <string>
#include <vector>

namespace stepstone::reporttest {

/// Steps of the tiny run's only start, and its KB's segment width.
inline constexpr int kSteps = 200;
inline constexpr int kWidth = 10;

/// `stepstone evolve` on a tiny source config (population 8, 4 generations,
/// one start of 200 steps, a KB of width 10 observed every generation, seed 5);
/// `retain_all` keeps every genome.
void make_run(const std::filesystem::path& path, bool retain_all = false);

/// `stepstone campaign` on a tiny campaign in `dir`: one source run as above,
/// its KB and randomized twin, then none / sum / sum-rand x 2 seeds of 2
/// generations on the target task.
void make_campaign(const std::filesystem::path& dir);

/// The relative paths that index.html refers to (src, data and href values).
std::vector<std::string> references(const std::string& html);

/// Every entry of a directory (names, sorted), but the -wal and -shm files
/// that SQLite readers of a WAL database (a run being written) leave beside it.
std::vector<std::string> entries(const std::filesystem::path& dir);

}  // namespace stepstone::reporttest
