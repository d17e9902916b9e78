#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "db/connection.hpp"
#include "kb/knowledge_base.hpp"

namespace stepstone::db {

/// A knowledge base as stored in a database file.
struct StoredKb {
    std::int64_t id = 0;
    std::string name;
    std::optional<std::uint64_t> randomized_seed;  ///< set for a `kb randomize` output
    kb::KnowledgeBase kb{kb::KbParams{}};
};

/// Name, parameters and size of a stored KB (no segments loaded).
struct KbSummary {
    std::int64_t id = 0;
    std::string name;
    kb::KbParams params;
    std::optional<std::uint64_t> randomized_seed;
    std::int64_t segments = 0;
};

/// Writes a whole KB (parameters, sources, segments) under `name`; returns its id.
/// Run inside the caller's transaction for atomicity.
std::int64_t insert_kb(Connection& connection, const std::string& name, const kb::KnowledgeBase& kb,
                       std::optional<std::uint64_t> randomized_seed = std::nullopt);

/// Brings a stored KB up to date after observations made at `generation`:
/// every source, the segments from `previous_size` on, and the older
/// segments credited at `generation` (their last update). Run inside the
/// caller's transaction (evolve: the generation's).
void update_kb(Connection& connection, std::int64_t kb_id, const kb::KnowledgeBase& kb, std::size_t previous_size,
               std::int64_t generation);

/// Every KB of a file, in id order.
std::vector<KbSummary> list_kbs(Connection& connection);

/// Loads the KB called `name`, or the file's only KB when `name` is empty.
/// Throws DataError naming the file when there is none, several (without a
/// name), or the named one is missing; DatabaseError when a stored segment is
/// malformed (wrong blob size, NaN, count < 1).
StoredKb load_kb(Connection& connection, const std::string& name = "");

/// "within_delta" or "nearest".
const char* to_string(kb::Match match);
/// Parses a match rule; throws ConfigError naming `what` otherwise.
kb::Match parse_match(const std::string& text, const std::string& what = "match");

}  // namespace stepstone::db
