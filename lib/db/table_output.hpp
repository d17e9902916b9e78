#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "db/connection.hpp"

namespace stepstone::db {

/// How query results are printed: `list` as the sqlite3 shell's `-header`
/// mode (fields joined by '|', NULL empty, reals as SQLite prints them), `csv` as RFC 4180 (a header row,
/// fields quoted when they hold a comma, quote or line break, NULL empty,
/// reals in their shortest exact form), which pandas.read_csv, R's read.csv
/// and Python's csv module load as is.
enum class TableFormat { list, csv };

/// One field as the format writes it.
std::string format_field(const std::string& text, TableFormat format);

/// Writes `prefix` then the statement's column names as a header row.
void write_header(std::ostream& out, const Statement& statement, TableFormat format,
                  const std::vector<std::string>& prefix = {});

/// Writes `prefix` values then the current row of `statement`. Blobs are
/// written as their size ("<blob of N bytes>").
void write_row(std::ostream& out, const Statement& statement, TableFormat format,
               const std::vector<std::string>& prefix = {});

}  // namespace stepstone::db
