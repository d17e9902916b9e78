#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "db/connection.hpp"
#include "kb/knowledge_base.hpp"

namespace stepstone::db {

/// Hex digest (XXH3, 128 bits) of a run file's scientific content: the run
/// rows (seed, task, treatment, config, counters), every generation's
/// statistics but its wall time, every individual's objectives, the stored
/// genomes, the checkpoints and the knowledge-base tables. Timings, creation
/// dates and the program version are left out, so two runs with the same
/// seed and config have the same digest whatever the thread count, and a
/// resumed run has the digest of an uninterrupted one.
std::string run_digest(Connection& connection);

/// Hex digest (XXH3, 128 bits) of a knowledge base's content: its parameters
/// (width, channels, delta, match rule), the randomized seed if any, and every
/// segment's values, cumulated reward and count, in id order. Provenance and
/// names are left out. A run shaped by a KB stores this digest, so resuming
/// it with a different KB is refused.
std::string kb_digest(const kb::KnowledgeBase& kb, std::optional<std::uint64_t> randomized_seed);

}  // namespace stepstone::db
