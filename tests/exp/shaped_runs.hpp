#pragma once

// Shaped target runs for the engine's tests (evolution_test.cpp,
// run_evolve_test.cpp): hand-made KBs whose r_max is known without running the
// code under test, and `stepstone evolve` on a tiny target config.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "kb/knowledge_base.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

namespace stepstone::exptest {

/// One ball of 24 (8 balls x 3 starts): the target task's reward of a ball.
inline constexpr double kBall = 1.0 / 24.0;

/// A tiny target config (3 starts of 200 steps, population 8, 2 generations,
/// seed 11), which evolve() reads from dir/t.json.
inline constexpr const char* kTarget = R"({
  "task": {"kind": "target", "steps_per_start": 200, "starts": 3},
  "ea": {"population_size": 8, "generations": 2},
  "seed": 11
})";

// A KB of width-20, 15-channel segments: one all-zero segment with average
// `near`, one with every value 5 (further than any robot behaviour, whose
// values lie in [0, 1]) with average `far`. Under match = nearest every
// policy segment matches the zero segment, so r_max = near for every policy.
kb::KnowledgeBase two_segment_kb(double near, double far, kb::Match match = kb::Match::nearest,
                                 std::size_t channels = 15, std::size_t width = 20);

/// Writes `kb` as the only KB, named "hand", of a new file.
void write_kb(const std::filesystem::path& path, const kb::KnowledgeBase& kb,
              std::optional<std::uint64_t> randomized_seed = std::nullopt);

/// `stepstone evolve --config dir/t.json --db dir/db --threads 2 --quiet` followed by `extra`.
test::CliResult evolve(const test::TempDir& dir, const std::string& db,
                       const std::vector<std::string>& extra);

}  // namespace stepstone::exptest
