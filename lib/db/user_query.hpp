#pragma once

#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "db/connection.hpp"
#include "db/table_output.hpp"

namespace stepstone::db {

/// One analysis query of queries/ (embedded in the binary).
struct UserQuery {
    std::string name;         ///< file name without ".sql", e.g. "policy_saliency"
    std::string summary;      ///< the first line of its header comment
    std::vector<std::string> parameters;  ///< its :named parameters, in order of appearance
    std::string_view sql;
};

/// Every query of queries/, sorted by name.
std::vector<UserQuery> user_queries();

/// The query called `name` (with or without ".sql"); throws ConfigError
/// listing the known names otherwise.
UserQuery find_user_query(const std::string& name);

/// Runs the query `name` on `connection` with `params` (name = value; the
/// name with or without its ':'), printing a header row and every result
/// row. Every parameter of the query must be given and every given one must
/// exist (ConfigError naming it and the query's parameters). A value that
/// reads whole as an integer is bound as one, else as a real if it reads
/// whole as a finite number, else as text ('quoted' forces text).
void run_user_query(Connection& connection, const std::string& name,
                    const std::vector<std::pair<std::string, std::string>>& params, std::ostream& out,
                    TableFormat format);

}  // namespace stepstone::db
