#pragma once

#include <string>

#include "db/connection.hpp"

namespace stepstone::db {

/// Hex digest (XXH3, 128 bits) of a run file's scientific content: the run
/// rows (seed, task, treatment, config, counters), every generation's
/// statistics but its wall time, every individual's objectives, the stored
/// genomes, the checkpoints and the knowledge-base tables. Timings, creation
/// dates and the program version are left out, so two runs with the same
/// seed and config have the same digest whatever the thread count, and a
/// resumed run has the digest of an uninterrupted one.
std::string run_digest(Connection& connection);

}  // namespace stepstone::db
