#pragma once

#include <filesystem>

namespace stepstone::test {

// Builders of the bad database files that every command must refuse.

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

}  // namespace stepstone::test
