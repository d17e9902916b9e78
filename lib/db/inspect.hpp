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

/// Every user table (not sqlite_*) with its row count, sorted by name.
std::vector<TableCount> table_counts(Connection& connection);

/// Value of `key` in the meta table, or "" when absent.
std::string meta_value(Connection& connection, std::string_view key);
/// Sets `key` in the meta table.
void set_meta_value(Connection& connection, std::string_view key, std::string_view value);

}  // namespace stepstone::db
