#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "db/connection.hpp"

namespace stepstone::db {

/// A table of a database and its number of rows.
struct TableCount {
    std::string name;
    std::int64_t rows = 0;
};

/// SQLite's integrity check of the whole file: "ok", or its first problem.
std::string integrity_check(Connection& connection);

/// Every user table (not sqlite_*) with its row count, sorted by name.
std::vector<TableCount> table_counts(Connection& connection);

/// Whether `table` of the database has a column named `column`.
bool has_column(Connection& connection, std::string_view table, std::string_view column);
/// Whether the file records milestones (schema 0005: presses, pickups,
/// carry_steps, basket_releases in `individual`). Older files do not.
bool has_milestones(Connection& connection);

/// Value of `key` in the meta table, or "" when absent.
std::string meta_value(Connection& connection, std::string_view key);
/// Sets `key` in the meta table.
void set_meta_value(Connection& connection, std::string_view key, std::string_view value);

}  // namespace stepstone::db
