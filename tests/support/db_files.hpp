#pragma once

#include <filesystem>
#include <string>

namespace stepstone::test {

// Builders of the bad database files that every command must refuse.

/// Runs `sql` on `path` with raw SQLite, bypassing every stepstone check.
void raw_exec(const std::filesystem::path& path, const std::string& sql);

/// A valid stepstone database (current schema) with a few meta rows.
void make_stepstone_db(const std::filesystem::path& path);
/// An SQLite database of another application (application_id 0, one table).
void make_foreign_sqlite(const std::filesystem::path& path);
/// A stepstone database whose user_version is one above this program's.
void make_newer_stepstone(const std::filesystem::path& path);
/// A stepstone database cut to its first half (checkpointed first).
void make_truncated_stepstone(const std::filesystem::path& path);
/// A stepstone database stamped with schema version 0 (as before any migration).
void make_old_stepstone(const std::filesystem::path& path);
/// Turns a run file into one as schema version 4 wrote it: no milestone
/// columns in `individual` (migration 0005 removed again), user_version 4.
void make_schema4_run(const std::filesystem::path& path);

/// The run table's generations_done of a run file, opened read-only; `missing`
/// while the file or its run row does not exist yet (a writer still starting).
/// The default -1 reads as "not even generation 0"; pass -2 to tell that
/// apart from a run row written before generation 0.
int generations_done(const std::filesystem::path& path, int missing = -1);

/// The run digest of a run file (`stepstone db digest`), opened read-only.
std::string file_digest(const std::filesystem::path& path);
/// PRAGMA integrity_check of a file a killed writer may have left, opened for
/// writing as a resume does (so that its WAL is recovered first): "ok" when
/// sound, "absent" when the file does not exist.
std::string integrity_check(const std::filesystem::path& path);

}  // namespace stepstone::test
